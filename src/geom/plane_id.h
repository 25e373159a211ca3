// Plane identity of triangles, decided exactly, for RTT's shadow shafts (docs/design.md, "Plane
// identity"): coplanarity of shadow landings is decided by plane identity, never by a distance
// tolerance.
//
// Two triangles get the same plane id only when both are non-degenerate and every vertex of one
// lies exactly on the plane of the other (an exact orientation predicate on the float vertices).
// The converse is a matter of speed, not of correctness: triangles are grouped by the cell of an
// approximate normalized plane equation and verified exactly against the group's representative,
// so two exactly coplanar triangles whose approximate planes straddle a cell boundary get two
// ids for one plane. RTT then merely declines a tile it could have answered.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "geom/triangle.h"
#include "rtt/math.h"

namespace rtt {

/// Plane id of a degenerate triangle (its three vertices collinear or equal): it spans no plane.
inline constexpr uint32_t no_plane = 0xFFFFFFFFu;

/// Exact sign of det[a - d, b - d, c - d]: +1, 0 (the four points are coplanar) or -1.
/// A floating-point filter decides almost every call; the rest are evaluated exactly with
/// expansion arithmetic (Shewchuk 1997), so the answer is never a rounding artefact.
int orient3d_sign(const Vec3f& a, const Vec3f& b, const Vec3f& c, const Vec3f& d);

/// True when the three points are collinear (or coincide), exactly.
bool collinear(const Vec3f& a, const Vec3f& b, const Vec3f& c);

struct PlaneIds {
    /// Per triangle: its plane id, or no_plane for a degenerate triangle.
    std::vector<uint32_t> id;
    /// Per plane id: the index of the triangle that defines the plane (its first member).
    std::vector<uint32_t> representative;
};

/// Groups the triangles by exact plane identity (see the file comment). Deterministic: ids are
/// numbered in order of their representative's index.
PlaneIds compute_plane_ids(std::span<const TriangleVerts> triangles);

}  // namespace rtt
