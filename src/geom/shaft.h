// RTT's shaft (Dmitriev, Havran, Seidel 2004, section 3): four corner rays from one apex that
// bound every ray of a tile, and the five conservative tests that drop a triangle from the
// tile's relevant list only when NO ray of the tile can hit it.
//
// What "can hit" means here
// -------------------------
// A ray hits a triangle when the float watertight test of triangle.h says so (that test IS the
// definition every tracer shares), not when the real geometry says so: the two differ by
// rounding near edges and at grazing angles. So the tests below are robust versions of that
// float test's own conditions, with margins that bound its rounding. They are written in the
// watertight test's sheared frame, where everything a ray contributes is its shear
// (sx, sy, sz) = (d[kx], d[ky], 1) / d[kz] ("slopes"), with a permutation (kx, ky, kz) shared by
// the whole shaft (make_shaft refuses corners that do not share it).
//
// Slope space (the convexity argument)
// ------------------------------------
// For a fixed vertex V with a = V - O, the sheared coordinates ax = a[kx] - sx a[kz] and
// ay = a[ky] - sy a[kz] are affine in the slope s = (sx, sy), and so is each 2D edge function:
//     U(s) = cx by - cy bx      (the sx*sy terms cancel; U = det[c, b, d] / d[kz]),
// likewise V and W, and their sum det. A pinhole tile's directions lie in the cone spanned by
// its 4 corner directions; central projection onto d[kz] = 1 maps that cone onto the convex
// quad Q of the corner slopes. Every ray RTT answers from a list is checked to have its float
// slopes inside Q grown by a tolerance (the slope quad Q', make_shaft; trace_rtt checks it
// per ray), so an affine function of the slope is bounded on those rays by its values at Q's
// corners plus eta times its gradient, where eta bounds how far Q' moves Q's corners.
//
// Error of the float test at a given float slope (u = 2^-24, |sx|, |sy| <= 1 because kz is the
// dominant axis; nA = max-norm of a, mA = |ax| + |ay|, A the exact V - O):
//     |ax - ax(exact)| <= u|A[kx]| + 2u|A[kz]| + u|ax| <= 3u nA + u|ax|
//     |U - U(exact)|   <= 3u (nC mB + nB mC) + 4u mB mC             (=: deltaU)
// (products of the two sheared coordinates, their rounding and the subtraction's). Combining:
// the float U of any checked ray is at most  max over corners of the float U + MU, with
//     MU = (6u + eta)(nC mB' + nB mC') + 10u mB' mC',
// where mB' bounds mB on Q' (corner values plus the move 2 eta nB plus rounding): twice deltaU
// (once at the corner, once at the inner ray) plus eta times the gradient bound
// |dU/dsx| + |dU/dsy| <= nC mB + nB mC. The same holds for V, W (cyclically) and their sum.
//
// The five tests (paper: two plane tests, three barycentric tests)
// ----------------------------------------------------------------
// Edge ("barycentric") tests. The float test rejects a ray whose U, V, W have both a negative
// and a positive value. A triangle is dropped when one of these holds at all 4 corners with the
// margins above, hence for every checked ray:
//   (a) some edge function < -M and another > +M                (mixed signs, both facings);
//   (b) some edge function < -M and det = U + V + W > MU+MV+MW, or the mirror image: then the
//       other two cannot both be <= 0 up to their error (they sum to more), so the signs mix.
//       This is the paper's "barycentric coordinate negative" lambda = U / det < 0, written
//       without the division (docs/design.md, "The five tests"): it needs det of one sign over the shaft.
// Plane ("before start", "beyond end") tests, along the dominant axis. The float t is
//     t = (U az + V bz + W cz) / det,  az = sz a[kz], ...
// a weighted mean of the vertex depths az, bz, cz with weights U, V, W of one sign (the test
// already failed otherwise); with rounding t lies in [min z (1 - 8.2u), max z (1 + 8.2u)] when
// all depths share a sign. In the shaft's "kz offsets" o = a[kz] * sign(d[kz]) (distance along
// the dominant axis, the same for every ray) and the ray's start and end offsets
// tmin |d[kz]| and tmax |d[kz]|, whose ranges over the tile are checked per ray:
//   (c) before the start: max o (1 + 16u) < lowest start offset, or max o < 0 (all vertices
//       behind the apex: t < 0 <= tmin; assumes no product underflows to zero, i.e. vertex
//       coordinates far from the denormal range);
//   (d) beyond the end: min o (1 - 16u) > highest end offset.
// These are the paper's plane tests in the form that bounds the float t (signs of points
// against a plane, affine in the ray). They cannot drop a triangle that sticks out on both
// sides of the shaft's start or end along kz; such triangles stay in the list, which is only
// slower.
//
// Whole-tile occluder (shadows; docs/design.md, "Shadow segments"): U, V, W all > their margins (or all < minus
// them) at the 4 corners and min o (1 - 16u) > highest start offset and max o (1 + 16u) < lowest
// end offset: then every checked ray's float test accepts (signs agree, det != 0) with
// t strictly inside its [tmin, tmax], so every segment of the tile is blocked.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "geom/triangle.h"
#include "rtt/math.h"
#include "simd/simd.h"

namespace rtt {

/// Sample index of corner lane i in a width x height grid: rays[0], rays[w-1], rays[(h-1)w],
/// rays[hw-1] (lanes 0, 1, 2, 3; around the quad the order is 0, 1, 3, 2).
inline int corner_sample(int width, int height, int lane) {
    const int x = (lane & 1) ? width - 1 : 0, y = (lane & 2) ? height - 1 : 0;
    return y * width + x;
}

/// Slope tolerance of the per-ray check: a ray whose float slopes lie this far outside the
/// corners' slope quad is still answered from the list (border samples round by a few ulps).
inline constexpr float shaft_slope_tolerance = 0x1p-20f;

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
/// (Scalar reference of the K-wide check in trace_rtt.)
bool shaft_accepts(const Shaft& shaft, const Ray& ray);

/// An axis-aligned box as two SIMD vectors (x, y, z, unused): traversal code narrows one
/// coordinate per split with a lane select, which avoids store-forwarding stalls.
struct BoxV {
    vfloat4 lo, hi;
    BoxV() = default;
    explicit BoxV(const Bbox3f& b) : lo(lanes(b.lo)), hi(lanes(b.hi)) {}
    static vfloat4 lanes(const Vec3f& v) { return vfloat4::setr(v.x, v.y, v.z, 0.f); }
};

/// Up to 4 half-spaces n . (x - org) >= c, one per SIMD lane, tested against boxes. A box is
/// declared outside only when it lies outside one of them by more than `tol` = 2^-18 sum |n_a|
/// times the largest |x_a - org_a| over the scene: far more than the test's own rounding
/// (differences, products, two sums and the float normal: below 5u sum |n_a| |x_a - org_a|), and
/// more than the distance by which the float watertight test can accept a ray that misses a
/// triangle (its sheared coordinates are off by up to about 4u |V - O|): a triangle such a ray
/// "hits" still meets the region. (Unused lanes: n = 0, c = -1.)
struct PlaneSet {
    vfloat4 nx, ny, nz;
    vfloat4 limit;  ///< c - tol

    /// Whether the box (its corners relative to org, each coordinate broadcast) may meet all 4
    /// half-spaces.
    RTT_FORCEINLINE bool meets(vfloat4 lx, vfloat4 ly, vfloat4 lz, vfloat4 hx, vfloat4 hy,
                               vfloat4 hz) const {
        const vfloat4 best =
            (max(nx * lx, nx * hx) + max(ny * ly, ny * hy)) + max(nz * lz, nz * hz);
        return none(best < limit);
    }
};

/// The region R covered by the rays a shaft accepts, for shaft culling of the kd-tree
/// (rtt_corners.h): the cone (4 planes of the grown quad through the apex), the slab of kz
/// offsets [o_lo, o_hi] between the rays' starts and ends, and optionally one more half-space
/// bounding the ends (the plane the rays end on: T's plane for primary rays, the receiver's
/// for shadows). Tests are conservative (PlaneSet).
///
/// Like Haines and Wallace's shafts, R also has a bounding box (`bounds`), and more: the planes
/// alone miss every box that is separated from R only along a world axis (a kd node beside the
/// one the corners cross, its face parallel to the cone's side: no plane of the cone has it
/// wholly outside), or that the cone only passes at other depths (a node under the ceiling
/// that the rays rising to it reach only farther on). So a box is also compared with the
/// cone's slice at the box's own depths: relative to the apex, a point of the cone at depth
/// z = x[kz] - org[kz] has lateral coordinates s z, with slopes s over the grown quad, which
/// lies within eta of the corners' slopes (an accepted ray's exact slopes are within u of its
/// float ones); over the box's depths within the slab, s z ranges between the products of the
/// extreme slopes and depths. Everything is relative to the apex, as every test here is
/// (absolute coordinates would round at the scene's magnitude, not at its extent from the
/// apex), and grown by PlaneSet's tolerance for an axis plane, 2^-18 times the scene's extent
/// along that axis from the apex, which exceeds the rounding of these products.
struct ShaftRegion {
    PlaneSet cone, slab;
    vfloat4 org;
    BoxV bounds;  ///< Holds R - org (class comment); lane 3 is 0.
    bool use_slab = true;

    ShaftRegion(const Shaft& s, const Bbox3f& scene, float o_lo, float o_hi)
        : org(BoxV::lanes(s.org)), kx_(s.kx), ky_(s.ky), kz_(s.kz), sign_z_(s.sign_z) {
        using vf = vfloat4;
        extent_ = max(abs(scene.lo - s.org), abs(scene.hi - s.org));
        const float slack = 2.f * s.eta + 0x1p-20f;  // the quad's lines move by 2^-21 more
        const vf sx = vf::load(s.sx), sy = vf::load(s.sy);
        slope_lo_[0] = reduce_min(sx)[0] - slack;
        slope_hi_[0] = reduce_max(sx)[0] + slack;
        slope_lo_[1] = reduce_min(sy)[0] - slack;
        slope_hi_[1] = reduce_max(sy)[0] + slack;
        cone.nx = vf::loadu(s.frustum_nx);
        cone.ny = vf::loadu(s.frustum_ny);
        cone.nz = vf::loadu(s.frustum_nz);
        cone.limit = vf(0.f) - tolerance(cone);
        // Slab: sign_z (x[kz] - org[kz]) >= o_lo and -sign_z (x[kz] - org[kz]) >= -o_hi. With
        // the rays starting at the apex and no end, the cone alone is the region (it is pointed:
        // its planes exclude everything behind the apex).
        use_slab = o_lo > 0.f || o_hi < pos_inf;
        n_[0][s.kz] = s.sign_z;
        n_[1][s.kz] = -s.sign_z;
        c_[0] = o_lo;
        c_[1] = -o_hi;
        load_slab();
    }
    /// Adds the half-space n . (x - org) >= c.
    void add_end_plane(const Vec3f& n, float c) {
        n_[2][0] = n.x;
        n_[2][1] = n.y;
        n_[2][2] = n.z;
        c_[2] = c;
        use_slab = true;
        load_slab();
    }
    /// The region of the same shaft and start ending at offset o_hi instead, and on the
    /// positive side of n . (x - org) >= c when `n` is given (else without that half-space):
    /// the cone is kept, only the slab changes.
    void set_end(float o_hi, const Vec3f* n, float c) {
        c_[1] = -o_hi;
        n_[2][0] = n ? n->x : 0.f;
        n_[2][1] = n ? n->y : 0.f;
        n_[2][2] = n ? n->z : 0.f;
        c_[2] = n ? c : -1.f;
        use_slab = true;
        load_slab();
    }
    RTT_FORCEINLINE bool meets(const BoxV& box) const {
        using vf = vfloat4;
        const vf dlo = box.lo - org, dhi = box.hi - org;
        if ((movemask((dlo <= bounds.hi) & (dhi >= bounds.lo)) & 7) != 7) return false;
        const vf lx(dlo[0]), ly(dlo[1]), lz(dlo[2]), hx(dhi[0]), hy(dhi[1]), hz(dhi[2]);
        if (!(movemask(slice_meets<4>({lx, ly, lz}, {hx, hy, hz})) & 1)) return false;
        return cone.meets(lx, ly, lz, hx, hy, hz) &&
               (!use_slab || slab.meets(lx, ly, lz, hx, hy, hz));
    }
    /// meets() for K boxes at once, one per lane (structure of arrays of box corners relative
    /// to nothing: absolute coordinates). Returns the lanes whose box may meet the region.
    template <int K>
    RTT_FORCEINLINE vbool<K> meets(const vfloat<K> (&lo)[3], const vfloat<K> (&hi)[3]) const {
        using vf = vfloat<K>;
        vf dlo[3], dhi[3];
        for (int a = 0; a < 3; ++a) {
            dlo[a] = lo[a] - vf(org[a]);
            dhi[a] = hi[a] - vf(org[a]);
        }
        vbool<K> in(true);
        for (int a = 0; a < 3; ++a)
            in &= (dlo[a] <= vf(bounds.hi[a])) & (dhi[a] >= vf(bounds.lo[a]));
        in &= slice_meets<K>(dlo, dhi);
        const auto plane = [&](const PlaneSet& p, int l) {
            const float nx = p.nx[l], ny = p.ny[l], nz = p.nz[l];
            const vf best =
                (max(vf(nx) * dlo[0], vf(nx) * dhi[0]) + max(vf(ny) * dlo[1], vf(ny) * dhi[1])) +
                max(vf(nz) * dlo[2], vf(nz) * dhi[2]);
            in &= best >= vf(p.limit[l]);
        };
        for (int l = 0; l < 4; ++l) plane(cone, l);
        if (use_slab)
            for (int l = 0; l < 3; ++l) plane(slab, l);
        return in;
    }

    /// Whether the box [lo, hi] (relative to the apex, within `bounds` along kz) may meet the
    /// cone's slice at the box's depths (class comment). K boxes at once, one per lane.
    template <int K>
    RTT_FORCEINLINE vbool<K> slice_meets(const vfloat<K> (&lo)[3], const vfloat<K> (&hi)[3]) const {
        using vf = vfloat<K>;
        const vf z0 = max(lo[kz_], vf(bounds.lo[kz_])), z1 = min(hi[kz_], vf(bounds.hi[kz_]));
        vbool<K> in(true);
        for (int i = 0; i < 2; ++i) {
            const int a = i == 0 ? kx_ : ky_;
            vf s_lo, s_hi;
            lateral_range<K>(i, z0, z1, s_lo, s_hi);
            const vf tol(slice_tol_[a]);
            in &= (lo[a] <= s_hi + tol) & (hi[a] >= s_lo - tol);
        }
        return in;
    }

private:
    /// The cone's extent along lateral axis i (kx, ky) over depths [z0, z1] relative to the apex,
    /// without tolerance: s z is bilinear, so its extremes are at the ends of both ranges.
    template <int K>
    RTT_FORCEINLINE void lateral_range(int i, vfloat<K> z0, vfloat<K> z1, vfloat<K>& lo,
                                       vfloat<K>& hi) const {
        using vf = vfloat<K>;
        const vf s0(slope_lo_[i]), s1(slope_hi_[i]);
        const vf p00 = s0 * z0, p01 = s0 * z1, p10 = s1 * z0, p11 = s1 * z1;
        lo = min(min(p00, p01), min(p10, p11));
        hi = max(max(p00, p01), max(p10, p11));
    }
    vfloat4 tolerance(const PlaneSet& p) const {
        using vf = vfloat4;
        return vf(0x1p-18f) * ((abs(p.nx) * vf(extent_.x) + abs(p.ny) * vf(extent_.y)) +
                               abs(p.nz) * vf(extent_.z));
    }
    void load_slab() {
        using vf = vfloat4;
        slab.nx = vf::setr(n_[0][0], n_[1][0], n_[2][0], n_[3][0]);
        slab.ny = vf::setr(n_[0][1], n_[1][1], n_[2][1], n_[3][1]);
        slab.nz = vf::setr(n_[0][2], n_[1][2], n_[2][2], n_[3][2]);
        slab.limit = vf::setr(c_[0], c_[1], c_[2], c_[3]) - tolerance(slab);
        load_bounds();
    }
    /// `bounds` for offsets [c_[0], -c_[1]] (class comment); unbounded without an end.
    void load_bounds() {
        const vfloat4 tol = vfloat4(0x1p-18f) * BoxV::lanes(extent_);
        for (int a = 0; a < 3; ++a) slice_tol_[a] = tol[a];
        const float o_lo = c_[0], o_hi = -c_[1];
        if (!(o_hi < pos_inf)) {
            bounds.lo = vfloat4(neg_inf);
            bounds.hi = vfloat4(pos_inf);
            return;
        }
        float lo[3], hi[3];
        const float z_lo = sign_z_ * (sign_z_ > 0.f ? o_lo : o_hi);
        const float z_hi = sign_z_ * (sign_z_ > 0.f ? o_hi : o_lo);
        lo[kz_] = z_lo;
        hi[kz_] = z_hi;
        for (int i = 0; i < 2; ++i) {
            vfloat4 s_lo, s_hi;
            lateral_range<4>(i, vfloat4(z_lo), vfloat4(z_hi), s_lo, s_hi);
            lo[i == 0 ? kx_ : ky_] = s_lo[0];
            hi[i == 0 ? kx_ : ky_] = s_hi[0];
        }
        bounds.lo = vfloat4::setr(lo[0], lo[1], lo[2], 0.f) - tol;
        bounds.hi = vfloat4::setr(hi[0], hi[1], hi[2], 0.f) + tol;
    }
    int kx_, ky_, kz_;
    float sign_z_;
    float slope_lo_[2], slope_hi_[2];  // slopes along kx, ky over the grown quad
    float slice_tol_[3];
    Vec3f extent_;
    float n_[4][3] = {};                               // unused lanes: n = 0,
    float c_[4] = {0.f, 0.f, -1.f, -1.f};              // c = -1: never separating
};

/// One triangle against the 4 corners.
struct CornerVerdict {
    uint32_t hit = 0;         ///< Lanes whose watertight test hits within [tmin, lane tmax].
    vfloat4 t;                ///< Their hit distances (other lanes: unspecified).
    bool relevant = true;     ///< False: no checked ray of the shaft can hit the triangle.
    bool blocks_all = false;  ///< Every checked ray hits it within its interval.
    float min_offset = 0.f;   ///< Smallest kz offset of the vertices (see the file comment).
};

/// The corners' own watertight tests (exactly intersect_watertight, lane by lane, against
/// [tmin, lane_tmax]) and the five conservative tests, sharing the sheared coordinates.
/// WantBlocker: also decide blocks_all (shadows).
template <bool WantBlocker>
RTT_FORCEINLINE CornerVerdict test_corners(const Shaft& s, const TriangleVerts& tri,
                                           vfloat4 lane_tmax) {
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
    const vf U = cx * by - cy * bx;
    const vf V = ax * cy - ay * cx;
    const vf W = bx * ay - by * ax;
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

    // Margins (file comment). nX: max-norm of the vertex; mX: max over corners of |x| + |y|.
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

}  // namespace rtt
