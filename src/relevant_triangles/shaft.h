// RTT's shaft (Dmitriev, Havran, Seidel 2004, section 3): four corner rays from one apex that
// bound every ray of a tile, and the per-ray check that a ray is one the shaft speaks for. The
// five conservative tests built on it are in conservative_tests.h, the region R its rays cover
// in region.h. "Can hit" means what the float watertight test of triangle.h says; slope space,
// the error bounds and the margins derived from them: docs/design.md, "The shaft and the per-ray
// check" and "The five tests, and why they are conservative".
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "geom/triangle.h"
#include "rtt/math.h"
#include "simd/isa.h"
#include "simd/simd.h"

namespace rtt {
inline namespace RTT_ISA_NS {

/// Sample index of corner lane i in a width x height grid: rays[0], rays[w-1], rays[(h-1)w],
/// rays[hw-1] (lanes 0, 1, 2, 3; around the quad the order is 0, 1, 3, 2).
inline int corner_sample(int width, int height, int lane) {
    const int x = (lane & 1) ? width - 1 : 0, y = (lane & 2) ? height - 1 : 0;
    return y * width + x;
}

/// What a shaft's rays ask: their closest hits (primary and reflected rays) or whether anything
/// blocks them (shadow segments).
enum class Query { closest_hit, any_hit };

struct alignas(16) Shaft {
    // Corner shear constants, bit-identical to WatertightRay of each corner ray (lanes 0..3).
    float sx[4], sy[4], sz[4];
    float tmin[4], tmax[4];
    /// Inner-ray check: a ray is inside when edge_nx[m] * sx + edge_ny[m] * sy >= edge_c[m]
    /// for the 4 edges of the slope quad (edge_c already includes the tolerance).
    float edge_nx[4], edge_ny[4], edge_c[4];
    /// The grown quad as 4 planes through the apex, world axes: every point org + t d of an
    /// accepted ray (t >= 0) has frustum_n[m] . (point - org) >= 0.
    float frustum_nx[4], frustum_ny[4], frustum_nz[4];
    Vec3f org;                   ///< The common apex.
    int kx = 0, ky = 1, kz = 2;  ///< Watertight permutation shared by the corners.
    float sign_z = 1.f;          ///< Sign of d[kz] for every ray.
    /// How far (max-norm, in slope units) the grown quad Q' moves the corners' slopes.
    float eta = 0.f;
    /// Ranges of the start offset tmin |d[kz]| and end offset tmax |d[kz]| that rays answered
    /// from the list must have (the corners' ranges, widened by 2^-16 relative).
    float start_lo = 0.f, start_hi = 0.f, end_lo = pos_inf, end_hi = pos_inf;
    /// The slope quad's fields (edges, frustum, eta) are set: make_shaft_quad succeeded.
    bool has_quad = false;
};

/// The 4 corner rays' directions and intervals as SIMD lanes, built in registers (a vector
/// loaded from scalars just stored would wait on store forwarding).
struct CornerLanes {
    Vec3v<4> dir;
    vfloat4 tmin, tmax;

    explicit CornerLanes(const Ray (&c)[4])
        : dir{vfloat4::setr(c[0].dir.x, c[1].dir.x, c[2].dir.x, c[3].dir.x),
              vfloat4::setr(c[0].dir.y, c[1].dir.y, c[2].dir.y, c[3].dir.y),
              vfloat4::setr(c[0].dir.z, c[1].dir.z, c[2].dir.z, c[3].dir.z)},
          tmin(vfloat4::setr(c[0].tmin, c[1].tmin, c[2].tmin, c[3].tmin)),
          tmax(vfloat4::setr(c[0].tmax, c[1].tmax, c[2].tmax, c[3].tmax)) {}
};

/// Builds the shaft of 4 corner rays (corner_sample order). Returns false when RTT cannot use
/// them: different origins, a corner whose watertight permutation differs from the others,
/// tmin < 0 or NaN values, or corner slopes that do not form a strictly convex quad (or one
/// so acute that the grown quad moves a corner by more than 2^-10).
bool make_shaft(const Ray (&corners)[4], Shaft& shaft);
/// make_shaft in two steps, for passes that often give up before they need the quad:
/// make_shaft_corners sets the corners' watertight constants, permutation and offsets (all that
/// the corners' own tests use) and refuses what make_shaft refuses about the rays;
/// make_shaft_quad then sets the slope quad, edges, frustum and eta (the five conservative
/// tests, regions and the per-ray check need them) and refuses what make_shaft refuses about
/// the quad.
bool make_shaft_corners(const Ray (&corners)[4], Shaft& shaft);
bool make_shaft_quad(Shaft& shaft);
/// Whether `shaft` has its quad, building it first when make_shaft_quad has not run (inline:
/// the corner pass asks before every triangle it tests).
inline bool complete_shaft(Shaft& shaft) {
    return shaft.has_quad || make_shaft_quad(shaft);
}

/// True when `ray` may be answered from the shaft's relevant list: same origin and watertight
/// permutation, float slopes inside the grown quad, start and end offsets inside the ranges.
/// (Scalar reference of the K-wide check of inner_rays.h.)
bool shaft_accepts(const Shaft& shaft, const Ray& ray);

}  // namespace RTT_ISA_NS
}  // namespace rtt
