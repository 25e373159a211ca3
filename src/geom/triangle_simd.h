// The watertight ray/triangle test of triangle.h for K rays at once (one ray per SIMD lane)
// against one triangle: the form packet tracing and RTT's inner rays need.
//
// Exactness: every lane evaluates exactly the float operations of intersect_watertight() in
// triangle.h, in the same order (no FMA: rtt compiles with -ffp-contract=off), with the same
// axis permutation, so a lane hits (and at which t) exactly when the scalar test does. Only
// the way the permuted coordinates are fetched differs, and fetching is not arithmetic:
//  * fast path: every active lane has the same permutation (kx, ky, kz), the usual case for
//    coherent rays. The triangle's vertices are permuted once and broadcast.
//  * general path: lanes differ; each lane picks its coordinates with selects.
//
// No per-triangle data is precomputed: the test's arithmetic depends on the ray's shear, and
// any precomputed form (Wald's projection, Woop's unit triangle) would round differently and
// break agreement with the scalar tracer. Triangles stay the 36-byte TriangleVerts.
#pragma once

#include <bit>
#include <type_traits>

#include "geom/triangle.h"
#include "simd/isa.h"
#include "simd/simd.h"

namespace rtt {
inline namespace RTT_ISA_NS {

/// Component k of v. Vec3f is three contiguous floats (checked below); indexing from &v.x
/// avoids the compare-and-branch chain Vec3f::operator[] compiles to.
RTT_FORCEINLINE float coord(const Vec3f& v, int k) {
    return (&v.x)[k];
}
static_assert(sizeof(Vec3f) == 3 * sizeof(float) && std::is_standard_layout_v<Vec3f>);

/// Lane by lane v[k] for k in {0, 1, 2}, given the masks k == 0 and k == 1.
template <int K>
RTT_FORCEINLINE vfloat<K> pick_axis(const Vec3v<K>& v, vbool<K> k_is_0, vbool<K> k_is_1) {
    return select(k_is_0, v.x, select(k_is_1, v.y, v.z));
}

/// WatertightRay for K rays, structure of arrays: per-lane axis permutation, shear and
/// interval. `tmax` is meant to shrink as hits are found (closest-hit search).
template <int K>
struct alignas(sizeof(vfloat<K>)) WatertightPacket {
    Vec3v<K> org;
    vfloat<K> sx, sy, sz;
    vfloat<K> tmin, tmax;
    vint<K> kx, ky, kz;
    /// When every active lane shares one permutation: `uniform`, the permutation, and the
    /// origins permuted by it (porg.x = org[ukx], porg.y = org[uky], porg.z = org[ukz]).
    bool uniform = false;
    int ukx = 0, uky = 1, ukz = 2;
    Vec3v<K> porg;

    WatertightPacket() = default;

    /// Per lane the constants of WatertightRay(Ray{org, dir, tmin, tmax}), bit for bit.
    /// `active` only decides whether the permutation is uniform; inactive lanes should hold
    /// finite values (a copy of an active ray) to keep the arithmetic free of slow denormals.
    RTT_FORCEINLINE WatertightPacket(Vec3v<K> org_, const Vec3v<K>& dir, vfloat<K> tmin_,
                                     vfloat<K> tmax_, vbool<K> active)
        : org(org_), tmin(tmin_), tmax(tmax_) {
        // kz = max_abs_axis(dir): x on ties with y or z, then y on ties with z.
        const vfloat<K> ax = abs(dir.x), ay = abs(dir.y), az = abs(dir.z);
        const vbool<K> x_max = (ax >= ay) & (ax >= az);
        kz = select(x_max, vint<K>(0), select(ay >= az, vint<K>(1), vint<K>(2)));
        vint<K> kx_ = select(kz == vint<K>(2), vint<K>(0), kz + vint<K>(1));
        vint<K> ky_ = select(kx_ == vint<K>(2), vint<K>(0), kx_ + vint<K>(1));
        const vfloat<K> dz = pick_axis<K>(dir, kz == vint<K>(0), kz == vint<K>(1));
        const vbool<K> flip = dz < vfloat<K>(0.f);  // keep the winding of the 2D edge functions
        kx = select(flip, ky_, kx_);
        ky = select(flip, kx_, ky_);
        sx = pick_axis<K>(dir, kx == vint<K>(0), kx == vint<K>(1)) / dz;
        sy = pick_axis<K>(dir, ky == vint<K>(0), ky == vint<K>(1)) / dz;
        sz = vfloat<K>(1.f) / dz;

        const uint32_t bits = movemask(active);
        if (bits == 0) return;
        const int lane = std::countr_zero(bits);
        const vbool<K> same = (kx == vint<K>(kx[lane])) & (ky == vint<K>(ky[lane]));
        uniform = (movemask(same) & bits) == bits;
        if (uniform) {
            ukx = kx[lane];
            uky = ky[lane];
            ukz = kz[lane];
            // Selected in registers: indexing org would put it in memory, and copying it
            // from there stalled on store forwarding (perf, `packet`).
            const auto axis = [&](int a) {
                return pick_axis<K>(org, vbool<K>(a == 0), vbool<K>(a == 1));
            };
            porg = {axis(ukx), axis(uky), axis(ukz)};
        }
    }

    /// Lane l's constants as one WatertightRay, bit for bit.
    WatertightRay lane(int l) const {
        return {{org.x[l], org.y[l], org.z[l]},
                kx[l],
                ky[l],
                kz[l],
                sx[l],
                sy[l],
                sz[l],
                tmin[l],
                tmax[l]};
    }
};

// 14 vectors plus one vector's room for the permutation fields: 240 bytes at K = 4, under four
// cache lines; the traversal keeps one per packet on its stack frame.
static_assert(sizeof(WatertightPacket<4>) == 15 * sizeof(vfloat<4>));
#ifdef RTT_HAVE_SIMD8
static_assert(sizeof(WatertightPacket<8>) == 15 * sizeof(vfloat<8>));
#endif
#ifdef RTT_HAVE_SIMD16
static_assert(sizeof(WatertightPacket<16>) == 15 * sizeof(vfloat<16>));
#endif

/// The vertices of a triangle relative to the rays' origin, permuted: a_kx = v0[kx] - org[kx]
/// and so on, as intersect_watertight's first step computes them.
template <int K>
struct RelativeTriangle {
    vfloat<K> a_kx, a_ky, a_kz, b_kx, b_ky, b_kz, c_kx, c_ky, c_kz;
};

/// intersect_watertight() from its first step's result `rel` (the rest of the test: shear, edge
/// functions, t), for callers that get `rel` without the subtractions (a common origin).
/// EarlyOut: return as soon as no lane's edge functions agree (a branch per triangle); without
/// it t is computed for every lane (no branch: for callers that mostly hit or cannot predict).
template <int K, bool EarlyOut = true>
RTT_FORCEINLINE vbool<K> intersect_watertight_relative(const WatertightPacket<K>& r,
                                                       vbool<K> active,
                                                       const RelativeTriangle<K>& rel,
                                                       vfloat<K>& t) {
    using vf = vfloat<K>;
    const vf ax = rel.a_kx - r.sx * rel.a_kz;
    const vf ay = rel.a_ky - r.sy * rel.a_kz;
    const vf bx = rel.b_kx - r.sx * rel.b_kz;
    const vf by = rel.b_ky - r.sy * rel.b_kz;
    const vf cx = rel.c_kx - r.sx * rel.c_kz;
    const vf cy = rel.c_ky - r.sy * rel.c_kz;
    const vf u = difference_of_products(cx, by, cy, bx);
    const vf v = difference_of_products(ax, cy, ay, cx);
    const vf w = difference_of_products(bx, ay, by, ax);
    const vf zero(0.f);
    const vbool<K> some_neg = (u < zero) | (v < zero) | (w < zero);
    const vbool<K> some_pos = (u > zero) | (v > zero) | (w > zero);
    vbool<K> hit = andnot(active, some_neg & some_pos);
    if constexpr (EarlyOut) {
        if (none(hit)) return hit;
    }
    const vf det = (u + v) + w;
    hit &= det != zero;
    const vf az = r.sz * rel.a_kz;
    const vf bz = r.sz * rel.b_kz;
    const vf cz = r.sz * rel.c_kz;
    t = ((u * az + v * bz) + w * cz) / det;
    return hit & (t >= r.tmin) & (t <= r.tmax);  // ordered compares also reject NaN
}

/// Lanes of `active` whose ray hits `tri` at t in [tmin, tmax] (inclusive, per lane); `t` is
/// set for those lanes (other lanes: unspecified). Lane i answers exactly like
/// intersect_watertight(WatertightRay(ray_i), tri, t).
template <int K, bool EarlyOut = true>
RTT_FORCEINLINE vbool<K> intersect_watertight(const WatertightPacket<K>& r, vbool<K> active,
                                              const TriangleVerts& tri, vfloat<K>& t) {
    using vf = vfloat<K>;
    vf a_kx, a_ky, a_kz, b_kx, b_ky, b_kz, c_kx, c_ky, c_kz;
    if (r.uniform) [[likely]] {
        // a[kx] = v0[kx] - org[kx], as the scalar code's a = v0 - org then a[kx].
        a_kx = vf(coord(tri.v0, r.ukx)) - r.porg.x;
        a_ky = vf(coord(tri.v0, r.uky)) - r.porg.y;
        a_kz = vf(coord(tri.v0, r.ukz)) - r.porg.z;
        b_kx = vf(coord(tri.v1, r.ukx)) - r.porg.x;
        b_ky = vf(coord(tri.v1, r.uky)) - r.porg.y;
        b_kz = vf(coord(tri.v1, r.ukz)) - r.porg.z;
        c_kx = vf(coord(tri.v2, r.ukx)) - r.porg.x;
        c_ky = vf(coord(tri.v2, r.uky)) - r.porg.y;
        c_kz = vf(coord(tri.v2, r.ukz)) - r.porg.z;
    } else {
        const Vec3v<K> a = Vec3v<K>(tri.v0) - r.org;
        const Vec3v<K> b = Vec3v<K>(tri.v1) - r.org;
        const Vec3v<K> c = Vec3v<K>(tri.v2) - r.org;
        const vbool<K> x0 = r.kx == vint<K>(0), x1 = r.kx == vint<K>(1);
        const vbool<K> y0 = r.ky == vint<K>(0), y1 = r.ky == vint<K>(1);
        const vbool<K> z0 = r.kz == vint<K>(0), z1 = r.kz == vint<K>(1);
        a_kx = pick_axis<K>(a, x0, x1);
        a_ky = pick_axis<K>(a, y0, y1);
        a_kz = pick_axis<K>(a, z0, z1);
        b_kx = pick_axis<K>(b, x0, x1);
        b_ky = pick_axis<K>(b, y0, y1);
        b_kz = pick_axis<K>(b, z0, z1);
        c_kx = pick_axis<K>(c, x0, x1);
        c_ky = pick_axis<K>(c, y0, y1);
        c_kz = pick_axis<K>(c, z0, z1);
    }
    return intersect_watertight_relative<K, EarlyOut>(
        r, active, RelativeTriangle<K>{a_kx, a_ky, a_kz, b_kx, b_ky, b_kz, c_kx, c_ky, c_kz}, t);
}

/// Closest hit per lane, with the one ordering of math.h's closer(): smaller t, then smaller
/// triangle index. tri = invalid_triangle (as int32: -1) means no hit yet.
template <int K>
struct PacketHit {
    vfloat<K> t = vfloat<K>(pos_inf);
    vint<K> tri = vint<K>(int32_t(invalid_triangle));

    /// Takes (t_new, id) in the lanes of `hit` where it is closer; returns those lanes.
    RTT_FORCEINLINE vbool<K> update(vbool<K> hit, vfloat<K> t_new, uint32_t id) {
        const vint<K> vid{int32_t(id)};
        const vbool<K> take = hit & ((t_new < t) | ((t_new == t) & ult(vid, tri)));
        t = select(take, t_new, t);
        tri = select(take, vid, tri);
        return take;
    }
};
static_assert(sizeof(PacketHit<4>) == 2 * sizeof(vfloat<4>));

}  // namespace RTT_ISA_NS
}  // namespace rtt
