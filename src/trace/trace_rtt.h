// The RTT tracers: relevant triangles tracing (Dmitriev, Havran, Seidel 2004, section 3;
// docs/design.md, "RTT exactness") behind the Tracer interface. The exactness argument is in
// docs/design.md, "RTT exactness".
//
// Per tile with shaft = true, "rtt":
//  1. A shaft is made from the 4 corner rays (geom/shaft.h). One front-to-back walk of the
//     kd-tree through the shaft (rtt_cull.h) enters the nodes whose box may meet the region R of
//     the rays answered from the list; every triangle of every leaf it enters goes through the
//     corners' watertight tests (the corners are answers too, trace_ray's) and the five
//     conservative tests. The corners' hits narrow R as the walk goes.
//  2. Primary and reflected tiles (intersect): R ends on the plane P of the corners' hits (exact
//     plane identity, geom/plane_id.h; the paper asks for one triangle). Tiles above 8x8
//     samples whose corners hit several planes take R up to the farthest hit's offset, without
//     P. Corners on several planes in a 4x4-sample tile, or a walk that would enter more nodes
//     than tracing the tile costs, end RTT for the tile at once: it is traced by 16-wide
//     packets. Otherwise the inner rays are intersected with the list K at a time
//     (rtt_inner.h); an inner answer is taken when the ray passes the shaft check and its
//     answer lies inside R; any other inner ray is traced.
//  3. Shadow tiles (occluded): when the corners and every active sample of the tile hit
//     triangles of one plane and the light is not on it (exact orientation), R ends at that
//     plane and is known before the walk:
//     an empty list means visible, a whole-tile occluder (CornerVerdict::blocks_all) blocked,
//     otherwise each inner segment is tested against the list (any hit).
// A tile may be a region of several of the renderer's 4x4-pixel tiles (RayTile::cell; at K = 1
// 16x16 pixels by default): it is one shaft like any tile, walked with a smaller budget
// (RttOptions::region_budget_divisor), and traced whole when it gives no list.
// Everything else (tiles without shaft, inner rays failing a check) is traced by the SIMD
// packet tracer, so answers always equal trace_ray's, ray for ray.
//
// At K = 1 and 2 (up to 8x8 samples, RttOptions::lean_max_samples) "rtt" takes rtt-paper's corner packet
// instead of the walk, stopped at the first sign of incoherence (the tile is then traced by the
// widest packets), with the walk's one-plane rule for the end of R (trace_rtt.cpp, measured in
// docs/benchmarks.md).
//
// "rtt-paper" keeps the paper's procedure and rules instead: the corners go through the tree as
// one SSE packet with the incoherence flag (rtt_corners.h), the nodes they leave out are shaft
// culled afterwards (collect_deferred), and a tile is answered only when the corners stayed
// coherent and, for primary rays, hit one triangle.
//
// Statistics: traced = corner rays and segments plus fallbacks, answered = rays answered from a
// list; rays = traced + answered (for shadows only active segments count; the corners of a
// shadow shaft are traced even when inactive, without being counted).
#pragma once

#include <memory>

#include "rtt/kdtree.h"
#include "rtt/scene.h"
#include "rtt/rtt_options.h"
#include "rtt/tracer.h"

namespace rtt {

// make_rtt_tracer (include/rtt/rtt_options.h) builds both, from RttOptions::rules.

}  // namespace rtt
