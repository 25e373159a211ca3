// The SAH split search of the top levels: K planes per axis, evenly spaced in the node, with
// exact triangle counts (Shevtsov, Soupikov and Kapustin 2007, "Highly parallel fast kd-tree
// construction for interactive ray tracing of dynamic scenes"). One pass over the node's
// triangles, in parallel over all cores, and no sorted event lists to keep.
#pragma once

#include <span>

#include "kdtree/kd_events.h"
#include "kdtree/kd_sah.h"
#include "rtt/kdtree.h"

namespace rtt::kd {

/// Planes per axis. The SAH cost of a plane between two bins' is exact; only the choice of
/// planes is coarser than the sweep's, which takes over below the top levels.
inline constexpr int binned_planes = 255;

/// Cheapest split of the node `box` holding `items` among the binned planes of the three
/// axes, costed as find_split costs them (same counts, planar triangles on either side). Ties go
/// to the lower axis, then the lower plane. axis = -1 when the box is too thin for the planes
/// or no plane makes progress.
SplitChoice find_binned_split(std::span<const TriBox> items, const Bbox3f& box,
                              const KdBuildConfig& config);

}  // namespace rtt::kd
