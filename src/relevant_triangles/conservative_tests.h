// The five conservative tests of RTT (Dmitriev, Havran, Seidel 2004, section 3) and the corners'
// own watertight tests, in one pass over a triangle: a triangle is dropped from a tile's
// relevant list only when NO ray the shaft accepts (shaft.h) can hit it. The tests (two edge
// tests, the plane tests before the start and beyond the end), the margins MU, MV, MW and the
// whole-tile occluder of shadows are derived in docs/design.md, "The five tests, and why they
// are conservative"; the assumptions (no underflow to zero) in its "Assumptions".
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "geom/triangle.h"
#include "relevant_triangles/shaft.h"
#include "simd/isa.h"

namespace rtt {
inline namespace RTT_ISA_NS {

/// One triangle against the 4 corners.
struct CornerVerdict {
    uint32_t hit = 0;         ///< Lanes whose watertight test hits within [tmin, lane tmax].
    vfloat4 t;                ///< Their hit distances (other lanes: unspecified).
    bool relevant = true;     ///< False: no checked ray of the shaft can hit the triangle.
    bool blocks_all = false;  ///< Every checked ray hits it within its interval.
    float min_offset = 0.f;   ///< Smallest kz offset o = a[kz] sign(d[kz]) of the vertices.
};

/// The corners' own watertight tests (exactly intersect_watertight, lane by lane, against
/// [tmin, lane_tmax]) and the five conservative tests, sharing the sheared coordinates.
/// Query::any_hit: also decide blocks_all (shadows).
template <Query Q>
RTT_FORCEINLINE CornerVerdict test_corners(const Shaft& s, const TriangleVerts& tri,
                                           vfloat4 lane_tmax) {
    constexpr bool WantBlocker = Q == Query::any_hit;
    using vf = vfloat4;
    constexpr float u = 0x1p-24f;
    const Vec3f a3 = tri.v0 - s.org, b3 = tri.v1 - s.org,
                c3 = tri.v2 - s.org;  // as the scalar test
    const float akx = a3[s.kx], aky = a3[s.ky], akz = a3[s.kz];
    const float bkx = b3[s.kx], bky = b3[s.ky], bkz = b3[s.kz];
    const float ckx = c3[s.kx], cky = c3[s.ky], ckz = c3[s.kz];
    const vf sx = vf::load(s.sx), sy = vf::load(s.sy);
    const vf ax = vf(akx) - sx * vf(akz);
    const vf ay = vf(aky) - sy * vf(akz);
    const vf bx = vf(bkx) - sx * vf(bkz);
    const vf by = vf(bky) - sy * vf(bkz);
    const vf cx = vf(ckx) - sx * vf(ckz);
    const vf cy = vf(cky) - sy * vf(ckz);
    const vf U = difference_of_products(cx, by, cy, bx);
    const vf V = difference_of_products(ax, cy, ay, cx);
    const vf W = difference_of_products(bx, ay, by, ax);
    const vf zero(0.f);
    CornerVerdict out;

    // The corners' own tests: intersect_watertight() step for step.
    const vbool4 some_neg = (U < zero) | (V < zero) | (W < zero);
    const vbool4 some_pos = (U > zero) | (V > zero) | (W > zero);
    const vf det = (U + V) + W;
    vbool4 hit = andnot(det != zero, some_neg & some_pos);
    if (any(hit)) {
        const vf sz = vf::load(s.sz);
        const vf az = sz * vf(akz), bz = sz * vf(bkz), cz = sz * vf(ckz);
        out.t = ((U * az + V * bz) + W * cz) / det;
        hit &= (out.t >= vf::load(s.tmin)) & (out.t <= lane_tmax);
        out.hit = movemask(hit);
    }

    // A triangle a corner hits is relevant (the corners are accepted rays); its vertex offsets
    // still matter to the primary end filter.
    const float oa = akz * s.sign_z, ob = bkz * s.sign_z, oc = ckz * s.sign_z;
    const float max_o = std::max({oa, ob, oc}), min_o = std::min({oa, ob, oc});
    out.min_offset = min_o;
    if (out.hit) {
        out.relevant = true;
        if (!WantBlocker || out.hit != 0xF) return out;
    }

    // Margins (design.md). nX: max-norm of the vertex; mX: max over corners of |x| + |y|.
    const float nA = std::max({std::fabs(akx), std::fabs(aky), std::fabs(akz)});
    const float nB = std::max({std::fabs(bkx), std::fabs(bky), std::fabs(bkz)});
    const float nC = std::max({std::fabs(ckx), std::fabs(cky), std::fabs(ckz)});
    const float grow = 2.f * s.eta + 8.f * u, keep = 1.f + 4.f * u;
    const float mA = reduce_max(abs(ax) + abs(ay))[0] * keep + grow * nA;
    const float mB = reduce_max(abs(bx) + abs(by))[0] * keep + grow * nB;
    const float mC = reduce_max(abs(cx) + abs(cy))[0] * keep + grow * nC;
    const float k1 = 6.f * u + s.eta, k2 = 10.f * u, fudge = 1.f + 0x1p-8f, tiny = 0x1p-100f;
    const float MU = (k1 * (nC * mB + nB * mC) + k2 * mB * mC) * fudge + tiny;
    const float MV = (k1 * (nA * mC + nC * mA) + k2 * mA * mC) * fudge + tiny;
    const float MW = (k1 * (nB * mA + nA * mB) + k2 * mA * mB) * fudge + tiny;
    const uint32_t u_neg = movemask(U < vf(-MU)), u_pos = movemask(U > vf(MU));
    const uint32_t v_neg = movemask(V < vf(-MV)), v_pos = movemask(V > vf(MV));
    const uint32_t w_neg = movemask(W < vf(-MW)), w_pos = movemask(W > vf(MW));
    const bool any_neg = u_neg == 0xF || v_neg == 0xF || w_neg == 0xF;
    const bool any_pos = u_pos == 0xF || v_pos == 0xF || w_pos == 0xF;
    // det = (U + V) + W rounds by at most 2u (|U| + |V| + |W|).
    const vf det_margin =
        vf((MU + MV + MW) * fudge) + vf(2.f * u * fudge) * ((abs(U) + abs(V)) + abs(W));
    const bool det_pos = movemask(det > det_margin) == 0xF;
    const bool det_neg = movemask(det < -det_margin) == 0xF;

    const bool before_start =
        max_o < 0.f || max_o * (1.f + 16.f * u) < s.start_lo * (1.f - 4.f * u);
    const bool beyond_end = min_o * (1.f - 16.f * u) > s.end_hi * (1.f + 4.f * u);
    out.relevant = out.hit || !((any_neg && any_pos) || (det_pos && any_neg) ||
                                (det_neg && any_pos) || before_start || beyond_end);
    const bool inside = (u_pos == 0xF && v_pos == 0xF && w_pos == 0xF) ||
                        (u_neg == 0xF && v_neg == 0xF && w_neg == 0xF);
    out.blocks_all = inside && min_o * (1.f - 16.f * u) > s.start_hi * (1.f + 4.f * u) &&
                     max_o * (1.f + 16.f * u) < s.end_lo * (1.f - 4.f * u);
    return out;
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
