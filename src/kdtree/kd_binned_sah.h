// The SAH split search above the small nodes: binned, then refined to the exact planes near the
// best bin (Shevtsov, Soupikov and Kapustin 2007, "Highly parallel fast kd-tree construction for
// interactive ray tracing of dynamic scenes"; refinement as in Hunt, Mark and Stoll 2006).
// One counting pass over the node's triangles, in parallel over all cores in large nodes, and
// no sorted event lists to keep from node to node.
#pragma once

#include <span>

#include "kdtree/kd_events.h"
#include "kdtree/kd_sah.h"
#include "rtt/kdtree.h"

namespace rtt::kd {

/// Planes per axis of the bins for a node of n triangles: a few per triangle, since the
/// refinement, not the bins, places the plane; more in large nodes, where a wrong bin costs more.
int binned_planes_for(size_t n);

/// Cheapest split of the node `box` holding `items`, costed as the sweep costs it (exact counts,
/// planar triangles on either side): on the axis of the cheapest binned plane (the lower axis
/// at a tie), the cheapest of that plane and of every triangle bound between the planes around
/// it; ties to the lower plane.
/// When the box is too thin for the planes, every triangle bound is tried (find_exact_split).
/// axis = -1 when no plane makes progress.
SplitChoice find_binned_split(std::span<const TriBox> items, const Bbox3f& box,
                              const KdBuildConfig& config);

/// The sweep's choice over every triangle bound (sorting them once): for a node whose binned
/// choice is not worth taking, where a plane away from the best bin may still be.
SplitChoice find_exact_split(std::span<const TriBox> items, const Bbox3f& box,
                             const KdBuildConfig& config);

}  // namespace rtt::kd
