// The region R covered by the rays a shaft accepts (shaft.h), and the conservative test of
// axis-aligned boxes against it: what the walk (walk.h) and the culling of deferred nodes
// (deferred_nodes.cpp) enter, and what the relevant list must cover.
#pragma once

#include "relevant_triangles/shaft.h"
#include "relevant_triangles/tolerances.h"
#include "simd/isa.h"

namespace rtt {
inline namespace RTT_ISA_NS {

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
/// (corner_pass.h): the cone (4 planes of the grown quad through the apex), the slab of kz
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
        return vf(tolerance::box_test) * ((abs(p.nx) * vf(extent_.x) + abs(p.ny) * vf(extent_.y)) +
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
        const vfloat4 tol = vfloat4(tolerance::box_test) * BoxV::lanes(extent_);
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
    float n_[4][3] = {};                   // unused lanes: n = 0,
    float c_[4] = {0.f, 0.f, -1.f, -1.f};  // c = -1: never separating
};

}  // namespace RTT_ISA_NS
}  // namespace rtt
