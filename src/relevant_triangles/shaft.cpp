#include "relevant_triangles/shaft.h"

#include <bit>

#include "geom/triangle_simd.h"
#include "relevant_triangles/tolerances.h"

namespace rtt {
inline namespace RTT_ISA_NS {
namespace {

bool same_bits(const Vec3f& a, const Vec3f& b) {
    return std::bit_cast<uint32_t>(a.x) == std::bit_cast<uint32_t>(b.x) &&
           std::bit_cast<uint32_t>(a.y) == std::bit_cast<uint32_t>(b.y) &&
           std::bit_cast<uint32_t>(a.z) == std::bit_cast<uint32_t>(b.z);
}

}  // namespace

bool make_shaft(const Ray (&c)[4], Shaft& s) {
    return make_shaft_corners(c, s) && make_shaft_quad(s);
}

bool make_shaft_corners(const Ray (&c)[4], Shaft& s) {
    for (const Ray& r : c) {
        if (!is_finite(r.org) || !is_finite(r.dir) || !same_bits(r.org, c[0].org)) return false;
        if (!(r.tmin >= 0.f && r.tmin <= r.tmax)) return false;  // also rejects NaN
    }
    // The corners' WatertightRay constants, 4 lanes at once (WatertightPacket is
    // WatertightRay lane for lane, bit for bit): one permutation for all, or no shaft.
    const CornerLanes lanes(c);
    const WatertightPacket<4> w(Vec3v<4>(c[0].org), lanes.dir, lanes.tmin, lanes.tmax,
                                vbool4(true));
    if (!w.uniform || c[0].dir[w.ukz] == 0.f) return false;
    store(s.sx, w.sx);
    store(s.sy, w.sy);
    store(s.sz, w.sz);
    store(s.tmin, lanes.tmin);
    store(s.tmax, lanes.tmax);
    s.org = c[0].org;
    s.kx = w.ukx;
    s.ky = w.uky;
    s.kz = w.ukz;
    s.sign_z = c[0].dir[w.ukz] < 0.f ? -1.f : 1.f;
    s.has_quad = false;

    // Start / end offsets along the dominant axis, computed as shaft_accepts computes them.
    float so_lo = pos_inf, so_hi = 0.f, eo_lo = pos_inf, eo_hi = 0.f;
    for (const Ray& r : c) {
        const float dz = std::fabs(r.dir[s.kz]);
        const float so = r.tmin * dz, eo = r.tmax * dz;
        so_lo = std::min(so_lo, so);
        so_hi = std::max(so_hi, so);
        eo_lo = std::min(eo_lo, eo);
        eo_hi = std::max(eo_hi, eo);
    }
    constexpr float widen = tolerance::offset_range;
    s.start_lo = so_lo * (1.f - widen);
    s.start_hi = so_hi * (1.f + widen);
    s.end_lo = eo_lo * (1.f - widen);
    s.end_hi = eo_hi * (1.f + widen);
    return true;
}

bool make_shaft_quad(Shaft& s) {
    using vf = vfloat4;
    // The slope quad in cyclic order q = 0, 1, 3, 2, one edge per SIMD lane: edge m runs from
    // corner q[m] to corner q[m+1]. rot(k) holds the corners shifted by k.
    const float cx[4] = {s.sx[0], s.sx[1], s.sx[3], s.sx[2]},
                cy[4] = {s.sy[0], s.sy[1], s.sy[3], s.sy[2]};
    const auto rot = [](const float(&c)[4], int k) {
        return vf::setr(c[k & 3], c[(k + 1) & 3], c[(k + 2) & 3], c[(k + 3) & 3]);
    };
    const vf px = rot(cx, 0), py = rot(cy, 0), px1 = rot(cx, 1), py1 = rot(cy, 1);
    const vf ex = px1 - px, ey = py1 - py;                            // edge m
    const vf ex_next = rot(cx, 2) - px1, ey_next = rot(cy, 2) - py1;  // edge m + 1
    const vf ex_prev = px - rot(cx, 3), ey_prev = py - rot(cy, 3);    // edge m - 1
    // Turn at corner m + 1: cross(e_m, e_m+1). All of one sign, or the quad is refused. (The
    // region the check accepts is the intersection of the 4 half-planes, inside the quad's
    // convex hull even if rounding let a nearly flat corner through.)
    const vf turn = ex * ey_next - ey * ex_next;
    const uint32_t positive = movemask(turn > vf(0.f)), negative = movemask(turn < vf(0.f));
    if (positive != 0xF && negative != 0xF) return false;
    const float o = positive == 0xF ? 1.f : -1.f;

    // (nx, ny): unit normal of edge m into the quad, which is n . s >= c. The float check
    // accepts n . s >= c - tolerance; its rounding (n and c within 2u, the products and the
    // sum: below 12u = 2^-20.4 for |s| <= 1) is covered by growing the lines by tolerance +
    // 2^-20 for the quad Q' whose corners define eta.
    const vf inv_len = vf(o) / sqrt(ex * ex + ey * ey);
    const vf nx = -ey * inv_len, ny = ex * inv_len;
    const vf cc = nx * px + ny * py;
    store(s.edge_nx, nx);
    store(s.edge_ny, ny);
    store(s.edge_c, cc - vf(tolerance::slope));
    // Moving the lines out by `grown` moves corner m (edges p = m - 1 and m meet there) by v
    // with n_p . v = n_m . v = -grown: v = -grown (n_p + n_m) / (1 + n_p . n_m).
    const float grown = tolerance::slope + 0x1p-20f;
    const vf inv_len_prev = vf(o) / sqrt(ex_prev * ex_prev + ey_prev * ey_prev);
    const vf pnx = -ey_prev * inv_len_prev, pny = ex_prev * inv_len_prev;  // normal of edge m - 1
    const vf cosine = vf(1.f) + (pnx * nx + pny * ny);
    if (!all(cosine > vf(1e-6f))) return false;
    const vf move = vf(grown) * max(abs(pnx + nx), abs(pny + ny)) / cosine;
    const float eta = reduce_max(move)[0];
    if (!(eta <= tolerance::max_quad_move)) return false;
    // Rounding in the computation above is below 2^-20 relative; the factor covers it.
    s.eta = eta * (1.f + 0x1p-16f);
    // A point org + t d (t > 0) has slopes d[kx] / d[kz], d[ky] / d[kz] exactly, within u of the
    // float slopes the check saw: inside the grown lines moved by 2^-21 more. Multiplying
    // n . s >= c by |d[kz]| = sign_z d[kz] gives a plane through the apex.
    alignas(16) float plane[3][4];
    store(plane[s.kx], vf(s.sign_z) * nx);
    store(plane[s.ky], vf(s.sign_z) * ny);
    store(plane[s.kz], vf(-s.sign_z) * (cc - vf(grown + 0x1p-21f)));
    store(s.frustum_nx, vf::load(plane[0]));
    store(s.frustum_ny, vf::load(plane[1]));
    store(s.frustum_nz, vf::load(plane[2]));
    s.has_quad = true;
    return true;
}

bool shaft_accepts(const Shaft& s, const Ray& r) {
    if (!same_bits(r.org, s.org)) return false;
    const WatertightRay w(r);
    if (w.kx != s.kx || w.ky != s.ky || w.kz != s.kz) return false;
    for (int m = 0; m < 4; ++m)
        if (!(s.edge_nx[m] * w.sx + s.edge_ny[m] * w.sy >= s.edge_c[m])) return false;
    const float dz = std::fabs(r.dir[s.kz]);
    const float so = r.tmin * dz, eo = r.tmax * dz;
    return so >= s.start_lo && so <= s.start_hi && eo >= s.end_lo && eo <= s.end_hi;
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
