// The RTT tracers: relevant triangles tracing (Dmitriev, Havran, Seidel 2004, section 3;
// ALGORITHM.md "RTT for a tile") behind the Tracer interface. The exactness argument is in
// docs/design.md, "RTT exactness".
//
// Per tile with shaft = true:
//  1. A shaft is made from the 4 corner rays (geom/shaft.h); the corners are traced as one SSE
//     packet with trace_ray's semantics (they are answers too), every triangle of every leaf
//     they reach goes through the five conservative tests, and the nodes they leave out are
//     kept for shaft culling (rtt_corners.h).
//  2. Primary and reflected tiles (intersect): when all 4 corners hit triangles of one plane P
//     (exact plane identity, geom/plane_id.h; the paper asks for one triangle), the list is
//     completed by shaft culling of the region ending at P, and the inner rays are intersected
//     with it K at a time (rtt_inner.h). An inner answer is taken when the ray passes the shaft
//     check and its answer lies inside the covered region; any other inner ray is traced.
//  3. Shadow tiles (occluded): when every sample of the tile hit a triangle of one plane and the
//     light is not on it (exact orientation), the region ends at that plane: an empty list means
//     visible, a whole-tile occluder (CornerVerdict::blocks_all) blocked, otherwise each inner
//     segment is tested against the list (any hit).
// Everything else (tiles without shaft, corners on several planes, a region whose culling would
// cost more than tracing, inner rays failing a check) is traced by the SIMD packet tracer, so
// answers always equal trace_ray's, ray for ray.
//
// "rtt-paper" keeps the paper's rules instead: the corners must be coherent (rtt_corners.h) and,
// for primary rays, hit one triangle.
//
// Statistics: traced = corner rays and segments plus fallbacks, answered = rays answered from a
// list; rays = traced + answered (for shadows only active segments count; the corners of a
// shadow shaft are traced even when inactive, without being counted).
#pragma once

#include <memory>

#include "rtt/kdtree.h"
#include "rtt/scene.h"
#include "rtt/tracer.h"

namespace rtt {

/// The "rtt" tracer over `scene` and `tree` (both must outlive it). Computes the triangles'
/// plane ids at construction.
std::unique_ptr<Tracer> make_rtt_tracer(const Scene& scene, const KdTree& tree);

/// The "rtt-paper" tracer: the paper's conditions (coherent corners; one triangle).
std::unique_ptr<Tracer> make_rtt_paper_tracer(const Scene& scene, const KdTree& tree);

}  // namespace rtt
