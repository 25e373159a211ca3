// Coherent rays through the BVH in packets of the ISA's widest vector (4x4 samples of a tile),
// one traversal per direction octant: each node's children are culled by one test of the
// packet's frustum, and the survivors tested against every lane at once, so rays that travel
// together (a tile's samples, reflections off one curved mirror) share the traversal.
// Exact: the frustum passes every child a lane's own widened slab test passes, and a lane's
// box tests keep every box holding a hit of its ray (docs/design.md, "The BVH for arbitrary
// rays"; PacketRays::subtract may cull more than the single ray's), its triangles tested with
// the packet form of the one watertight test, so every lane's hit is trace_bvh's bit for bit. Lanes
// whose direction has a zero or tiny component take the single-ray kernel, which handles those
// axes.
#include <algorithm>
#include <array>
#include <bit>
#include <cfloat>
#include <cstddef>
#include <cstring>

#include "core/platform.h"
#include "geom/triangle_simd.h"
#include "simd/simd.h"
#include "trace/blocker_cache.h"
#include "trace/octant_groups.h"
#include "trace/packet_blocks.h"
#include "trace/trace_bvh.h"
#include "trace/trace_ray.h"

namespace rtt {
inline namespace RTT_ISA_NS {
namespace {

constexpr int K = simd_max_width;
using vf = vfloat<K>;
using vb = vbool<K>;
/// Packets traced as one traversal where their lanes share direction signs: two (8x4 samples)
/// beat one and four (docs/benchmarks.md, "Arbitrary rays").
constexpr int group_size = 2;

/// Up to K rays as vectors, and the per-lane constants of the node test.
struct PacketRays {
    Vec3v<K> org, dir;
    vf tmin, tmax;
    vf inv[3], org_inv[3];
    vf t_margin, far_t_margin;  ///< As trace_bvh.cpp's BoxRay's, per lane.
    /// Every traced lane's direction has one sign per axis (else traversals go by octant);
    /// the faces each axis enters and leaves by, at byte offsets from a child's lo.x.
    bool same_signs = false;
    uint32_t enter[3] = {}, leave[3] = {};
    /// Every traced lane starts at the same point (bit for bit: a camera, a light): a
    /// triangle's vertices relative to it are then one subtraction for all lanes.
    bool common_origin = false;
    vb active;                 ///< Lanes traced here.
    bool nonneg_tmin = false;  ///< Every traced lane's tmin >= 0 (widen_interval).
    /// Face distances as (face - org) * inv, not face * inv - org * inv: where the origin's
    /// rounding term would more than double a lane's margin (a direction nearly parallel to
    /// an axis plane, far from 0 on that axis: shadow rays from a light on a wall to points on
    /// it), the margin it needs culled nothing near such rays (docs/design.md, "The BVH for
    /// arbitrary rays").
    bool subtract = false;
    uint32_t single = 0;  ///< Lanes left to the single-ray kernel.

    PacketRays() = default;
    /// The lanes `used` of `packet`; the others must hold finite rays (a copy of a used one).
    PacketRays(const RayPacket<K>& packet, uint32_t used, const Bbox3f& bounds) {
        org = {vf::load(packet.org[0]), vf::load(packet.org[1]), vf::load(packet.org[2])};
        dir = {vf::load(packet.dir[0]), vf::load(packet.dir[1]), vf::load(packet.dir[2])};
        tmin = vf::load(packet.tmin);
        tmax = vf::load(packet.tmax);
        // BoxLanes' constants (trace_bvh.h), written out here: made through BoxLanes the
        // shadow packets ran 4 % slower (`bench_trace` office `Shadow/bvh`, 2026-12-07).
        const vf* dv[3] = {&dir.x, &dir.y, &dir.z};
        const vf* ov[3] = {&org.x, &org.y, &org.z};
        vb odd(false);
        vf dist(0.f), dmax(0.f), org_t(0.f);
        for (int a = 0; a < 3; ++a) {
            inv[a] = vf(1.f) / *dv[a];
            org_inv[a] = *ov[a] * inv[a];
            odd |= (*dv[a] == vf(0.f)) | !(abs(inv[a]) <= vf(0x1p40f));
            dist = max(dist, max(abs(vf(bounds.lo[a]) - *ov[a]), abs(vf(bounds.hi[a]) - *ov[a])));
            dmax = max(dmax, abs(*dv[a]));
            org_t = max(org_t, abs(org_inv[a]));
        }
        single = movemask(odd) & used;
        restrict_to(used & ~single);
        nonneg_tmin = (movemask(tmin >= vf(0.f)) & used) == used;
        const vf scale_plain = min(dist / dmax, vf(FLT_MAX));
        subtract = (movemask(org_t * vf(0x1p-6f) > scale_plain) & used & ~single) != 0;
        if (const uint32_t traced = used & ~single) {
            const int l = std::countr_zero(traced);
            const auto same = [&](vf v) {
                return movemask(as_int(v) == vint<K>(as_int(v)[l])) & traced;
            };
            common_origin = (same(org.x) & same(org.y) & same(org.z)) == traced;
        }
        const vf scale = subtract ? scale_plain : scale_plain + org_t * vf(0x1p-6f);
        t_margin = vf(2.f * kd_margin) * min(scale, vf(FLT_MAX));
        far_t_margin = far_margin(t_margin, 2.f * kd_margin);
    }

    /// Traces only the lanes `lanes`: sets `active`, and whether they share direction signs
    /// with the faces those signs enter and leave by.
    void restrict_to(uint32_t lanes) {
        active = vb::from_bits(lanes);
        same_signs = true;
        const vf* dv[3] = {&dir.x, &dir.y, &dir.z};
        uint32_t negative = 0;
        for (int a = 0; a < 3; ++a) {
            const uint32_t neg = signbits(*dv[a]) & lanes;
            same_signs &= neg == 0 || neg == lanes;
            negative |= neg ? 1u << a : 0u;
        }
        // Offsets from a child's lo.x: lo is the node's first member.
        static_assert(offsetof(BvhNode<bvh_width>, lo) == 0);
        box_faces<bvh_width>(negative, enter, leave);
    }

    /// Lanes of `lanes` whose widened interval in child `c`'s box meets [tmin, tmax]; their
    /// widened entry distances in `near`. The lanes share direction signs (restrict_to).
    template <int W>
    RTT_FORCEINLINE vb test(const BvhNode<W>& n, int c, vb lanes, vf tmax_now, vf& near) const {
        return subtract ? test_with<true>(n, c, lanes, tmax_now, near)
                        : test_with<false>(n, c, lanes, tmax_now, near);
    }

private:
    template <bool Subtract, int W>
    RTT_FORCEINLINE vb test_with(const BvhNode<W>& n, int c, vb lanes, vf tmax_now,
                                 vf& near) const {
        static_assert(W == bvh_width);
        const char* base = reinterpret_cast<const char*>(&n.lo[0][c]);
        const vf* o[3] = {&org.x, &org.y, &org.z};
        const auto face = [&](uint32_t offset, int a) {
            const float f = *reinterpret_cast<const float*>(base + offset);
            if constexpr (Subtract)
                return (vf(f) - *o[a]) * inv[a];
            else
                return mul_sub(vf(f), inv[a], org_inv[a]);
        };
        const vf enter_t = max(max(face(enter[0], 0), face(enter[1], 1)), face(enter[2], 2));
        const vf leave_t = min(min(face(leave[0], 0), face(leave[1], 1)), face(leave[2], 2));
        vf far;
        if (nonneg_tmin)
            widen_interval<true>(enter_t, leave_t, 2.f * kd_margin, t_margin, far_t_margin, near,
                                 far);
        else
            widen_interval(enter_t, leave_t, 2.f * kd_margin, t_margin, far_t_margin, near, far);
        return lanes & (max(near, tmin) <= min(far, tmax_now));
    }
};

/// The packet as one frustum, for one W-lane test of a node's children: per axis the extremes
/// of the active lanes' origins and inverse directions (one sign per axis), so every lane's
/// interval in a box lies in the frustum's. Widened twice as much as a lane's test, it passes
/// every child some lane's own test passes (docs/design.md, "The BVH for arbitrary rays").
template <int W>
struct PacketFrustum {
    using vw = vfloat<W>;
    float o_near[3], o_far[3];  ///< The origins giving the smallest entry, the largest exit.
    float inv_lo[3], inv_hi[3];
    uint32_t enter[3], leave[3];  ///< PacketRays' face offsets.
    float inv_near[3];  ///< Of inv_lo and inv_hi, the one giving the smaller entry in front.
    float tmin, t_margin, far_t_margin;
    bool nonneg_tmin;

    /// Over the active lanes of `m` packets that share direction signs (their face offsets).
    PacketFrustum(const PacketRays* const* parts, int m) {
        const vf inf(pos_inf), ninf(neg_inf);
        const auto lowest = [&](auto field) {
            vf v = select(parts[0]->active, field(*parts[0]), inf);
            for (int i = 1; i < m; ++i) v = min(v, select(parts[i]->active, field(*parts[i]), inf));
            return reduce_min(v)[0];
        };
        const auto highest = [&](auto field) {
            vf v = select(parts[0]->active, field(*parts[0]), ninf);
            for (int i = 1; i < m; ++i)
                v = max(v, select(parts[i]->active, field(*parts[i]), ninf));
            return reduce_max(v)[0];
        };
        const PacketRays& p = *parts[0];
        // Parts that all start at one point (bit for bit: a camera, a light) bound their origins
        // by that point, without reductions.
        float origin[3];
        bool one_origin = true;
        for (int i = 0; i < m && one_origin; ++i) {
            const PacketRays& r = *parts[i];
            const int l = std::countr_zero(movemask(r.active));
            const float o[3] = {r.org.x[l], r.org.y[l], r.org.z[l]};
            if (i == 0) std::memcpy(origin, o, sizeof o);
            one_origin = r.common_origin && std::memcmp(origin, o, sizeof o) == 0;
        }
        for (int a = 0; a < 3; ++a) {
            // dir > 0: (face - org) * inv is least at the largest origin, greatest at the
            // smallest; dir < 0 the other way round. Each bound is then the lesser (greater) of
            // the two products with the inverse directions' extremes.
            const bool positive = p.enter[a] < p.leave[a];
            const auto org = [a](const PacketRays& r) {
                return a == 0 ? r.org.x : a == 1 ? r.org.y : r.org.z;
            };
            const auto inv = [a](const PacketRays& r) { return r.inv[a]; };
            o_near[a] = one_origin ? origin[a] : positive ? highest(org) : lowest(org);
            o_far[a] = one_origin ? origin[a] : positive ? lowest(org) : highest(org);
            inv_lo[a] = lowest(inv);
            inv_hi[a] = highest(inv);
            enter[a] = p.enter[a];
            leave[a] = p.leave[a];
        }
        for (int a = 0; a < 3; ++a) inv_near[a] = enter[a] < leave[a] ? inv_lo[a] : inv_hi[a];
        tmin = lowest([](const PacketRays& r) { return r.tmin; });
        nonneg_tmin = true;
        for (int i = 0; i < m; ++i) nonneg_tmin &= parts[i]->nonneg_tmin;
        t_margin = 2.f * highest([](const PacketRays& r) { return r.t_margin; });
        far_t_margin = far_margin(t_margin, 4.f * kd_margin);
    }

    /// Children whose box some lane may meet in [tmin, tfar]; the frustum's widened entry
    /// distances (a lower bound of every lane's) in `near`.
    RTT_FORCEINLINE uint32_t test(const BvhNode<W>& n, float tfar, vw& near) const {
        return nonneg_tmin ? test_with<true>(n, tfar, near) : test_with<false>(n, tfar, near);
    }

private:
    template <bool NonNegTmin>
    RTT_FORCEINLINE uint32_t test_with(const BvhNode<W>& n, float tfar, vw& near) const {
        const char* base = reinterpret_cast<const char*>(&n.lo[0][0]);
        vw tn(neg_inf), tf(pos_inf);
        for (int a = 0; a < 3; ++a) {
            const vw e = vw::load(reinterpret_cast<const float*>(base + enter[a])) - vw(o_near[a]);
            const vw l = vw::load(reinterpret_cast<const float*>(base + leave[a])) - vw(o_far[a]);
            // With tmin >= 0 a negative entry distance loses to tmin (widen_interval): the
            // inverse giving the smaller entry of a box in front is enough.
            if constexpr (NonNegTmin)
                tn = max(tn, e * vw(inv_near[a]));
            else
                tn = max(tn, min(e * vw(inv_lo[a]), e * vw(inv_hi[a])));
            tf = min(tf, max(l * vw(inv_lo[a]), l * vw(inv_hi[a])));
        }
        vw far;
        widen_interval<NonNegTmin>(tn, tf, 4.f * kd_margin, vw(t_margin), vw(far_t_margin), near,
                                   far);
        // No mask of the slots in use: an unused slot's empty box (lo +inf, hi -inf) gives
        // every lane's rays, whose direction has one sign per axis, an entry of +inf.
        return movemask(max(near, vw(tmin)) <= min(far, vw(tfar)));
    }
};

/// The vertices of lane l's triangle of a leaf block.
RTT_FORCEINLINE TriangleVerts triangle_of(const BvhTriangles4& q, int l) {
    return {{q.v0[0][l], q.v0[1][l], q.v0[2][l]},
            {q.v1[0][l], q.v1[1][l], q.v1[2][l]},
            {q.v2[0][l], q.v2[1][l], q.v2[2][l]}};
}

/// Starts loading a child the packet will visit: a node's four cache lines, or a leaf's first
/// block (the node's fetch is what a packet step waits on).
template <int W>
RTT_FORCEINLINE void prefetch_child(const Bvh<W>& bvh, uint32_t child) {
    const char* p = child & bvh_leaf_bit
                        ? reinterpret_cast<const char*>(&bvh.blocks[(child & ~bvh_leaf_bit) >> 3])
                        : reinterpret_cast<const char*>(&bvh.nodes[child]);
    // A node's boxes and children; its child count, on a line of its own, is not read. Leaf
    // blocks are 160 bytes, so a block may start mid-line: every line up to its last byte.
    const size_t size = child & bvh_leaf_bit ? sizeof(BvhTriangles4) : offsetof(BvhNode<W>, count);
    prefetch_bytes(p, size);
}

/// At most this many lanes in a leaf's box: each is tested alone, against four triangles at a
/// time (WatertightRay4), rather than the packets against each triangle: 1-3 % faster with
/// 16 lanes, nothing with 8 (docs/benchmarks.md, "Arbitrary rays").
constexpr int few_lanes = K >= 16 ? 4 : 0;

/// traverse() for M packets whose lanes share direction signs, as one: each node's children
/// are culled by one W-lane test of the packets' common frustum, and a survivor is entered when
/// some packet's lanes pass it. Subtrees are ordered by the frustum's entry distance, one
/// number for all lanes. A leaf is tested by the live lanes whose own test passed its box, as
/// packets, or one lane at a time where they are few (few_lanes).
/// `blockers` (any hit, may be null): tested on every lane first; blockers found are noted.
template <int W, bool AnyHit, int M>
void traverse_frustum(const Bvh<W>& bvh, const PacketRays* const* rays, PacketHit<K>* best,
                      vb* blocked, BlockerCache* blockers) {
    using vw = vfloat<W>;
    const PacketFrustum<W> frustum(rays, M);
    /// One packet's watertight constants, live lanes and common origin.
    struct Part {
        WatertightPacket<K> wp;
        vb alive;
        // A common origin, permuted as the watertight test permutes (wp.uniform): the origin's
        // coordinates to subtract from each vertex once for all lanes.
        bool relative;
        float po[3];
        int axes[3];
        int origin_of;  ///< The first part with the same po and axes (its relative vertices).
    };
    Part part[M];
    for (int m = 0; m < M; ++m) {
        const PacketRays& r = *rays[m];
        Part& p = part[m];
        p.wp = WatertightPacket<K>(r.org, r.dir, r.tmin, r.tmax, r.active);
        p.alive = r.active;
        p.relative = r.common_origin && p.wp.uniform;
        const int lane = std::countr_zero(movemask(r.active));
        p.po[0] = p.wp.porg.x[lane];
        p.po[1] = p.wp.porg.y[lane];
        p.po[2] = p.wp.porg.z[lane];
        p.axes[0] = p.wp.ukx;
        p.axes[1] = p.wp.uky;
        p.axes[2] = p.wp.ukz;
        p.origin_of = m;
        // Bit for bit: -0 and 0 subtract differently.
        for (int o = 0; o < m; ++o)
            if (std::memcmp(p.po, part[o].po, sizeof p.po) == 0 &&
                std::equal(p.axes, p.axes + 3, part[o].axes)) {
                p.origin_of = o;
                break;
            }
    }
    if constexpr (AnyHit) {
        if (blockers) {
            bool done = true;
            for (int m = 0; m < M; ++m) {
                Part& p = part[m];
                const vb hit = blocked_by(*blockers, p.wp, p.alive);
                blocked[m] |= hit;
                p.alive = andnot(p.alive, hit);
                done &= none(p.alive);
            }
            if (done) return;
        }
    }
    const vf ninf(neg_inf);
    // The farthest any live lane may still reach: what a subtree must start before.
    const auto reach = [&] {
        vf r = select(part[0].alive, part[0].wp.tmax, ninf);
        for (int m = 1; m < M; ++m) r = max(r, select(part[m].alive, part[m].wp.tmax, ninf));
        return reduce_max(r)[0];
    };
    float tfar = reach();
    struct Entry {
        uint32_t child;
        float near;
        uint32_t lanes[M];  ///< A leaf's: per packet the lanes whose own test passed its box.
    };
    // Lane l of packet m alone against the leaf blocks [first, first + count), four triangles
    // at a time: the packet test's operations lane by lane, so the same t and verdicts.
    // Whether it hit.
    const auto leaf_alone = [&](int m, int l, uint32_t first, uint32_t count) {
        Part& p = part[m];
        float tmax = p.wp.tmax[l];
        const vb lane = vb::from_bits(1u << l);
        bool hit = false;
        for_each_leaf_hit(bvh, first, count, WatertightRay4(p.wp.lane(l)), p.wp.tmin[l], tmax,
                          [&](const BvhTriangles4& q, int i, float t) {
                              hit = true;
                              if constexpr (AnyHit) {
                                  blocked[m] |= lane;
                                  p.alive = andnot(p.alive, lane);
                                  if (blockers) blockers->note(q.id[i], triangle_of(q, i));
                              } else {
                                  // inclusive tmax, as the packet test's
                                  p.wp.tmax = select(best[m].update(lane, vf(t), q.id[i]), vf(t),
                                                     p.wp.tmax);
                                  tmax = p.wp.tmax[l];
                              }
                              return AnyHit;
                          });
        return hit;
    };
    Entry stack[(W - 1) * bvh_max_depth + W];
    int top = 0;
    uint32_t cur = 0;
    float cur_near = frustum.tmin;
    uint32_t cur_lanes[M];
    for (int m = 0; m < M; ++m) cur_lanes[m] = ~0u;
    for (;;) {
        if (cur & bvh_leaf_bit) {
            const uint32_t first = (cur & ~bvh_leaf_bit) >> 3, count = cur & 7u;
            bool hit_any = false;
            vb lanes[M];
            int count_lanes = 0;
            for (int m = 0; m < M; ++m) {
                lanes[m] =
                    part[m].alive & vb::from_bits(cur_lanes[m]) & (vf(cur_near) <= part[m].wp.tmax);
                count_lanes += std::popcount(movemask(lanes[m]));
            }
            if (count_lanes <= few_lanes) {
                for (int m = 0; m < M; ++m)
                    for (uint32_t bits = movemask(lanes[m]); bits; bits &= bits - 1)
                        hit_any |= leaf_alone(m, std::countr_zero(bits), first, count);
            } else {
                const auto some_lanes = [&] {
                    vb all = lanes[0];
                    for (int m = 1; m < M; ++m) all |= lanes[m];
                    return any(all);
                };
                for (uint32_t k = first; k < first + count && some_lanes(); ++k) {
                    const BvhTriangles4& q = bvh.blocks[k];
                    // The block's vertices relative to the common origin, permuted: the scalar
                    // test's subtractions, for the four triangles at once, and once for packets
                    // that share origin and permutation. Kept in memory: a lane is broadcast by the
                    // load port, where a permute would take a port the test's arithmetic needs
                    // (docs/benchmarks.md, "Arbitrary rays").
                    alignas(16) float rel4[3][3][4];
                    int rel_of = -1;  // the part whose origin rel4 holds
                    for (int m = 0; m < M; ++m) {
                        Part& p = part[m];
                        if (none(lanes[m])) continue;
                        if (p.relative && rel_of != p.origin_of) {
                            const float(*v[3])[4] = {q.v0, q.v1, q.v2};
                            for (int i = 0; i < 3; ++i)
                                for (int j = 0; j < 3; ++j)
                                    store(rel4[i][j],
                                          vfloat4::load(v[i][p.axes[j]]) - vfloat4(p.po[j]));
                            rel_of = p.origin_of;
                        }
                        for (int l = 0; l < 4; ++l) {
                            const uint32_t id = q.id[l];
                            if (id == invalid_triangle) continue;
                            vf t(0.f);
                            vb hit;
                            if (p.relative) {
                                const auto at = [&](int i, int j) { return vf(rel4[i][j][l]); };
                                const RelativeTriangle<K> rel{at(0, 0), at(0, 1), at(0, 2),
                                                              at(1, 0), at(1, 1), at(1, 2),
                                                              at(2, 0), at(2, 1), at(2, 2)};
                                hit = intersect_watertight_relative<K>(p.wp, lanes[m], rel, t);
                            } else {
                                hit = intersect_watertight<K>(p.wp, lanes[m], triangle_of(q, l), t);
                            }
                            // Most tests hit no lane: a branch, rather than updates in
                            // memory for every test.
                            if (none(hit)) continue;
                            hit_any = true;
                            if constexpr (AnyHit) {
                                blocked[m] |= hit;
                                lanes[m] = andnot(lanes[m], hit);
                                p.alive = andnot(p.alive, hit);
                                if (blockers) blockers->note(id, triangle_of(q, l));
                            } else {
                                // inclusive tmax: a later equal-t hit still reaches the index
                                // tie-break
                                p.wp.tmax = select(best[m].update(hit, t, id), t, p.wp.tmax);
                            }
                        }
                    }
                }
            }
            if (hit_any) {
                if constexpr (AnyHit) {
                    bool done = true;
                    for (int m = 0; m < M; ++m) done &= none(part[m].alive);
                    if (done) return;
                }
                tfar = reach();
            }
        } else {
            const BvhNode<W>& node = bvh.nodes[cur];
            vw near_w;
            uint32_t bits = frustum.test(node, tfar, near_w);
            alignas(64) float near[W];
            store(near, near_w);
            vb live[M];
            for (int m = 0; m < M; ++m) live[m] = part[m].alive & (vf(cur_near) <= part[m].wp.tmax);
            // This node's stacked children: nearest on top for closest hits; for any hit in slot
            // order, the builder's likeliest blocker first (bvh_build.cpp, order_for_any_hit).
            const int base = top;
            bool have = false;
            Entry next{};
            Entry later[W];
            int n_later = 0;
            while (bits) {
                const int c = std::countr_zero(bits);
                bits &= bits - 1;
                Entry e{node.child[c], near[c], {}};
                bool passes = false;
                if (e.child & bvh_leaf_bit) {
                    // A leaf is tested by the lanes whose own test passes its box: every
                    // packet's are needed.
                    for (int m = 0; m < M; ++m) {
                        vf lane_near;
                        e.lanes[m] =
                            movemask(rays[m]->test(node, c, live[m], part[m].wp.tmax, lane_near));
                        passes |= e.lanes[m] != 0;
                    }
                } else {
                    for (int m = 0; m < M; ++m) e.lanes[m] = ~0u;
                    for (int m = 0; m < M && !passes; ++m) {
                        vf lane_near;
                        passes = any(rays[m]->test(node, c, live[m], part[m].wp.tmax, lane_near));
                    }
                }
                if (!passes) continue;
                prefetch_child(bvh, e.child);
                if (!have) {
                    have = true;
                    next = e;
                    continue;
                }
                if constexpr (AnyHit) {  // slot order: the builder's likeliest blocker first
                    later[n_later++] = e;
                    continue;
                }
                if (e.near < next.near) std::swap(e, next);
                int j = top++;
                for (; j > base && stack[j - 1].near < e.near; --j) stack[j] = stack[j - 1];
                stack[j] = e;
            }
            while (n_later > 0) stack[top++] = later[--n_later];
            if (have) {
                cur = next.child;
                cur_near = next.near;
                std::copy_n(next.lanes, M, cur_lanes);
                continue;
            }
        }
        for (;;) {
            if (top == 0) return;
            const Entry& e = stack[--top];
            if (e.near <= tfar) {
                cur = e.child;
                cur_near = e.near;
                std::copy_n(e.lanes, M, cur_lanes);
                break;
            }
        }
    }
}

/// traverse() with the node test the packet's direction signs allow.
template <int W, bool AnyHit>
void traverse_packet(const Bvh<W>& bvh, const PacketRays& p, PacketHit<K>& best, vb& blocked,
                     BlockerCache* blockers) {
    if (!any(p.active)) return;
    const PacketRays* parts[1] = {&p};
    if (p.same_signs) return traverse_frustum<W, AnyHit, 1>(bvh, parts, &best, &blocked, blockers);
    // Lanes of differing signs: one frustum per direction octant (lanes are independent).
    PacketRays part = p;
    parts[0] = &part;
    for_each_octant_group(signbits(p.dir.x), signbits(p.dir.y), signbits(p.dir.z),
                          movemask(p.active), [&](uint32_t lanes, uint32_t) {
                              part.restrict_to(lanes);
                              traverse_frustum<W, AnyHit, 1>(bvh, parts, &best, &blocked, blockers);
                          });
}

/// traverse_packet for M packets: one traversal when all their lanes share direction signs.
template <int W, bool AnyHit, int M>
void traverse_group(const Bvh<W>& bvh, const PacketRays* const* p, PacketHit<K>* best, vb* blocked,
                    BlockerCache* blockers = nullptr) {
    bool together = true;
    for (int m = 0; m < M; ++m)
        together &= any(p[m]->active) && p[m]->same_signs &&
                    std::equal(p[0]->enter, p[0]->enter + 3, p[m]->enter);
    if (together) return traverse_frustum<W, AnyHit, M>(bvh, p, best, blocked, blockers);
    for (int m = 0; m < M; ++m)
        traverse_packet<W, AnyHit>(bvh, *p[m], best[m], blocked[m], blockers);
}

/// The PacketRays of group_size packets (the lanes used[m] of packet m), and pointers to them.
struct PacketGroup {
    PacketRays rays[group_size];
    const PacketRays* p[group_size];
    PacketGroup(const RayPacket<K>* const* packet, const uint32_t* used, const Bbox3f& bounds) {
        for (int m = 0; m < group_size; ++m) {
            rays[m] = PacketRays(*packet[m], used[m], bounds);
            p[m] = &rays[m];
        }
    }
};

/// Closest hits of the lanes used[m] of group_size packets, traced together where they can be
/// (traverse_group): out(m, hits) with packet m's in its lanes (misses in lanes not used).
template <int W, typename Out>
void trace_blocks(const Bvh<W>& bvh, const RayPacket<K>* const* packet, const uint32_t* used,
                  Out&& out) {
    const PacketGroup group(packet, used, bvh.padded_bounds);
    const PacketRays* const* p = group.p;
    PacketHit<K> best[group_size];
    vb unused[group_size];
    traverse_group<W, false, group_size>(bvh, p, best, unused);
    for (int m = 0; m < group_size; ++m) {
        if (const uint32_t single = p[m]->single) {  // lanes the packet left to single rays
            alignas(64) float t[K];
            alignas(64) int32_t tri[K];
            store(t, best[m].t);
            store(tri, best[m].tri);
            for (uint32_t bits = single; bits; bits &= bits - 1) {
                const int i = std::countr_zero(bits);
                const Hit h = trace_bvh(bvh, packet[m]->get(i));
                t[i] = h.t;
                tri[i] = int32_t(h.tri);
            }
            best[m].t = vf::load(t);
            best[m].tri = vint<K>::load(tri);
        }
        out(m, best[m]);
    }
}

/// Writes the hits of a packet's lanes `used` to out[sample[lane]]. A whole block (every lane
/// used) is packet_height rows of packet_width consecutive samples, `row_stride` apart: written
/// a row at a time, where lane by lane the stores of a frame's hits were 4 % of `Primary/bvh`
/// (docs/benchmarks.md, "Arbitrary rays").
void store_hits(const PacketHit<K>& h, uint32_t used, const int* sample, int row_stride, Hit* out) {
    constexpr int pw = packet_width<K>, ph = packet_height<K>;
    static_assert(sizeof(Hit) == 2 * sizeof(float));
    alignas(64) float pairs[2 * K];  // (t, triangle) per lane: a Hit's layout
    storeu_pairs(pairs, h.t, as_float(h.tri));
    if (used == all_lanes<K>) {
        Hit* first = out + sample[0];
        for (int r = 0; r < ph; ++r)
            std::memcpy(static_cast<void*>(first + ptrdiff_t(r) * row_stride), pairs + 2 * pw * r,
                        sizeof(Hit) * pw);
        return;
    }
    for (uint32_t bits = used; bits; bits &= bits - 1) {
        const int i = std::countr_zero(bits);
        std::memcpy(static_cast<void*>(out + sample[i]), pairs + 2 * i, sizeof(Hit));
    }
}

/// Writes 1 (visible) or 0 (blocked: its bit in `blocked`) to out[sample[lane]] for a packet's
/// lanes `used`; a whole block a row at a time, as store_hits.
void store_visible(uint32_t blocked, uint32_t used, const int* sample, int row_stride,
                   uint8_t* out) {
    constexpr int pw = packet_width<K>, ph = packet_height<K>;
    if (used == all_lanes<K>) {
        // Per row of pw lanes, its pw bytes: byte l is 1 unless bit l is set (little endian).
        static constexpr auto row_bytes = [] {
            std::array<uint32_t, 1u << pw> table{};
            for (uint32_t bits = 0; bits < table.size(); ++bits)
                for (int l = 0; l < pw; ++l)
                    table[bits] |= uint32_t(!((bits >> l) & 1u)) << (8 * l);
            return table;
        }();
        uint8_t* first = out + sample[0];
        for (int r = 0; r < ph; ++r)
            std::memcpy(first + ptrdiff_t(r) * row_stride,
                        &row_bytes[(blocked >> (pw * r)) & ((1u << pw) - 1u)], pw);
        return;
    }
    for (uint32_t bits = used; bits; bits &= bits - 1) {
        const int i = std::countr_zero(bits);
        out[sample[i]] = uint8_t(!((blocked >> i) & 1u));
    }
}

/// The lane bits of the lanes used[m] of group_size packets that some triangle blocks, in
/// bits[m]; the packets traced together where they can be. `blockers` as in traverse_frustum.
template <int W>
void blocked_blocks(const Bvh<W>& bvh, const RayPacket<K>* const* packet, const uint32_t* used,
                    uint32_t* bits, BlockerCache* blockers = nullptr) {
    const PacketGroup group(packet, used, bvh.padded_bounds);
    const PacketRays* const* p = group.p;
    PacketHit<K> unused[group_size];
    vb blocked[group_size];
    for (vb& b : blocked) b = vb(false);
    traverse_group<W, true, group_size>(bvh, p, unused, blocked, blockers);
    for (int m = 0; m < group_size; ++m) {
        bits[m] = movemask(blocked[m]) & used[m] & ~p[m]->single;
        for (uint32_t odd = p[m]->single; odd; odd &= odd - 1) {
            const int i = std::countr_zero(odd);
            if (occluded_bvh(bvh, packet[m]->get(i))) bits[m] |= 1u << i;
        }
    }
}

/// Hands the blocks `each` yields to group(packets, used, samples) group_size at a time; the
/// last group is filled up with empty blocks (used 0).
template <typename Each, typename Group>
void in_groups(Each&& each, Group&& group) {
    RayPacket<K> held[group_size];
    uint32_t used[group_size] = {};
    int sample[group_size][K];
    const RayPacket<K>* packets[group_size];
    const int* samples[group_size];
    for (int m = 0; m < group_size; ++m) {
        packets[m] = &held[m];
        samples[m] = sample[m];
    }
    int n = 0;
    each([&](const RayPacket<K>& packet, uint32_t active, const int* s) {
        held[n] = packet;
        used[n] = active;
        std::copy_n(s, K, sample[n]);
        if (++n < group_size) return;
        group(packets, used, samples);
        n = 0;
    });
    if (n == 0) return;
    for (int m = n; m < group_size; ++m) used[m] = 0;
    group(packets, used, samples);
}

/// Calls block(packet, used, sample) for each packet of K consecutive rays (sample: each
/// lane's ray index, below 2^31).
template <typename Block>
void for_each_run(std::span<const Ray> rays, Block&& block) {
    RayPacket<K> packet;
    int sample[K];
    for (size_t first = 0; first < rays.size(); first += K) {
        const size_t n = std::min(size_t(K), rays.size() - first);
        for (size_t i = 0; i < size_t(K); ++i) {
            packet.set(int(i), rays[first + (i < n ? i : 0)]);
            sample[i] = int(first + i);
        }
        block(packet, n == size_t(K) ? ~0u >> (32 - K) : (1u << n) - 1u, sample);
    }
}

/// Calls fn(first, count) over [0, size) in chunks whose indices fit the blocks' int samples.
template <typename Fn>
void in_chunks(size_t size, Fn&& fn) {
    constexpr size_t chunk = size_t(1) << 30;
    for (size_t first = 0; first < size; first += chunk) fn(first, std::min(chunk, size - first));
}

}  // namespace

template <int W>
void trace_bvh_packets(const Bvh<W>& bvh, std::span<const Ray> rays, std::span<Hit> hits) {
    if (bvh.nodes.empty()) return std::fill(hits.begin(), hits.end(), Hit{});
    in_chunks(rays.size(), [&](size_t first, size_t count) {
        in_groups(
            [&](auto&& block) { for_each_run(rays.subspan(first, count), block); },
            [&](const RayPacket<K>* const* packet, const uint32_t* used, const int* const* sample) {
                trace_blocks(bvh, packet, used, [&](int m, const PacketHit<K>& h) {
                    store_hits(h, used[m], sample[m], packet_width<K>, hits.data() + first);
                });
            });
    });
}

template <int W>
void visible_bvh_packets(const Bvh<W>& bvh, std::span<const Ray> rays, std::span<uint8_t> visible) {
    if (bvh.nodes.empty()) return std::fill(visible.begin(), visible.end(), uint8_t(1));
    in_chunks(rays.size(), [&](size_t first, size_t count) {
        in_groups(
            [&](auto&& block) { for_each_run(rays.subspan(first, count), block); },
            [&](const RayPacket<K>* const* packet, const uint32_t* used, const int* const* sample) {
                uint32_t blocked[group_size] = {};
                blocked_blocks(bvh, packet, used, blocked);
                for (int m = 0; m < group_size; ++m)
                    store_visible(blocked[m], used[m], sample[m], packet_width<K>,
                                  visible.data() + first);
            });
    });
}

template <int W>
void trace_bvh_tile(const Bvh<W>& bvh, const RayTile& tile, std::span<Hit> hits) {
    if (bvh.nodes.empty()) return std::fill(hits.begin(), hits.end(), Hit{});
    in_groups(
        [&](auto&& block) {
            for_each_ray_block<K>(
                tile, [](int) { return true; }, block);
        },
        [&](const RayPacket<K>* const* packet, const uint32_t* used, const int* const* sample) {
            trace_blocks(bvh, packet, used, [&](int m, const PacketHit<K>& h) {
                store_hits(h, used[m], sample[m], tile.width, hits.data());
            });
        });
}

template <int W>
uint64_t visible_bvh_segments(const Bvh<W>& bvh, const SegmentTile& tile,
                              std::span<uint8_t> visible, BlockerCache& blockers) {
    uint64_t traced = 0;
    for (size_t i = 0; i < tile.points.size(); ++i) visible[i] = 0;
    const auto wanted = [&](int s) { return tile.active[size_t(s)] != 0; };
    in_groups(
        [&](auto&& block) { for_each_segment_block<K>(tile, wanted, block); },
        [&](const RayPacket<K>* const* packet, const uint32_t* used, const int* const* sample) {
            uint32_t blocked[group_size] = {};
            if (!bvh.nodes.empty()) blocked_blocks(bvh, packet, used, blocked, &blockers);
            for (int m = 0; m < group_size; ++m) {
                store_visible(blocked[m], used[m], sample[m], tile.width, visible.data());
                traced += uint64_t(std::popcount(used[m]));
            }
        });
    return traced;
}

template void trace_bvh_packets<bvh_width>(const Bvh<bvh_width>&, std::span<const Ray>,
                                           std::span<Hit>);
template void visible_bvh_packets<bvh_width>(const Bvh<bvh_width>&, std::span<const Ray>,
                                             std::span<uint8_t>);
template void trace_bvh_tile<bvh_width>(const Bvh<bvh_width>&, const RayTile&, std::span<Hit>);
template uint64_t visible_bvh_segments<bvh_width>(const Bvh<bvh_width>&, const SegmentTile&,
                                                  std::span<uint8_t>, BlockerCache&);

}  // namespace RTT_ISA_NS
}  // namespace rtt
