#include "trace/shadow_frustum.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "geom/triangle_simd.h"
#include "simd/simd.h"
#include "trace/packet_blocks.h"
#include "trace/root_clip.h"
#include "trace/trace_packet.h"
#include "trace/trace_ray.h"

namespace rtt {
inline namespace RTT_ISA_NS {
namespace {

constexpr int K = simd_max_width;
constexpr int pw = packet_width<K>, ph = packet_height<K>;
/// A chunk is cw x ch blocks, one per lane of the frusta: 16x16 points at K = 16, 8x8 at
/// K = 8, 4x4 at K = 4.
constexpr int cw = K == 16 ? 4 : 2, ch = K / cw;
using vf = vfloat<K>;
using vb = vbool<K>;

/// Largest |slope| of a segment against the chunk's dominant axis (76 degrees off it): the
/// slack below is sized for it.
constexpr float max_slope = 4.f;

/// The segments of one block of the chunk and what is known of them.
struct Block {
    WatertightPacket<K> wp;
    vf inv[3], t0, t1, t_scale;  ///< As trace_ray's: re-derive a lane's interval in a leaf.
    uint32_t in = 0;    ///< Lanes with an active segment.
    uint32_t open = 0;  ///< Of those, the lanes no blocker has been found for yet.
};

/// The blocks' bounding frusta, lane j = block j, in the chunk's frame: the dominant axis kz
/// (direction sign sigma) and the two others kx, ky. A point p of a segment L + t w, t in
/// [0, 1], has z = sigma (p[kz] - L[kz]) in [0, far] and x = p[kx] - L[kx] in
/// [umin z, umax z] (y likewise), umin and umax bounding the exact slopes w[kx] / |w[kz]|.
struct Frusta {
    vf umin, umax, vmin, vmax, far;
    float slack = 0.f;  ///< How far outside a plane a cell must lie to be left (file comment).
    uint32_t live = 0;  ///< Blocks with active segments.
    int kx = 0, ky = 1, kz = 2;
    float sigma = 1.f;
    Vec3f light;

    /// The blocks that may have a segment point in the cell [lo, hi] grown by trace_ray's
    /// margins. A plane is evaluated at the cell's extreme corner; the error of that float
    /// evaluation and the margins are both far below `slack` (docs/design.md).
    RTT_FORCEINLINE uint32_t enter(const float (&lo)[3], const float (&hi)[3]) const {
        const vf x0(lo[kx] - light[kx]), x1(hi[kx] - light[kx]);
        const vf y0(lo[ky] - light[ky]), y1(hi[ky] - light[ky]);
        float za = (lo[kz] - light[kz]) * sigma, zb = (hi[kz] - light[kz]) * sigma;
        if (za > zb) std::swap(za, zb);
        const vf zn(za), zf(zb), s(slack);
        const vb out = (x0 - max(umax * zn, umax * zf) > s) | (min(umin * zn, umin * zf) - x1 > s) |
                       (y0 - max(vmax * zn, vmax * zf) > s) | (min(vmin * zn, vmin * zf) - y1 > s) |
                       (zn > far + s) | (zf < -s);
        return ~movemask(out) & live;
    }
};

/// One deferred subtree: its node, its cell and the blocks that enter it.
struct Entry {
    const KdNode* node;
    float lo[3], hi[3];
    uint32_t blocks;
};

/// The lanes of `in` whose segment direction w leaves the frame: not strictly along sigma on
/// kz, or a slope beyond max_slope (NaN included). Sets u, v to the slopes.
RTT_FORCEINLINE uint32_t out_of_frame(const Frusta& f, const Vec3v<K>& w, uint32_t in, vf& u,
                                      vf& v) {
    const vf dz = w[f.kz] * vf(f.sigma);
    u = w[f.kx] / dz;
    v = w[f.ky] / dz;
    const vb ok = (dz > vf(0.f)) & (abs(u) <= vf(max_slope)) & (abs(v) <= vf(max_slope));
    return in & ~movemask(ok);
}

/// Widened past the rounding of a quotient (relative 2^-24, or absolute below the normal range).
RTT_FORCEINLINE vf widen_up(vf x) {
    return x + abs(x) * vf(0x1p-20f) + vf(0x1p-100f);
}
RTT_FORCEINLINE vf widen_down(vf x) {
    return x - abs(x) * vf(0x1p-20f) - vf(0x1p-100f);
}

/// Tests the open segments of the blocks in `e.blocks` against the leaf's triangles.
RTT_FORCEINLINE void visit_leaf(const KdTree& tree, std::span<const TriangleVerts> triangles,
                                const KdNode& leaf, const float (&lo)[3], const float (&hi)[3],
                                uint32_t blocks, const Vec3f& light,
                                Block* block, uint32_t& done) {
    const uint32_t count = leaf.triangle_count();
    if (!count) return;
    const uint32_t* ids = tree.leaf_triangles.data() + leaf.first_triangle();
    // Per block the open lanes whose interval in this cell, re-derived from its faces with
    // trace_ray's margins (a superset of trace_ray's), is not empty.
    uint32_t lane_mask[K];
    const vf margin(kd_margin);
    for (uint32_t m = blocks & ~done; m; m &= m - 1) {
        const int j = std::countr_zero(m);
        const Block& bl = block[j];
        vf ta = bl.t0, tb = bl.t1;
        for (int a = 0; a < 3; ++a) {
            const vf d0 = vf(lo[a] - light[a]) * bl.inv[a], d1 = vf(hi[a] - light[a]) * bl.inv[a];
            const vf near = min(d0, d1), far = max(d0, d1);
            ta = max(near - (abs(near) + bl.t_scale) * margin, ta);
            tb = min(far + (abs(far) + bl.t_scale) * margin, tb);
        }
        lane_mask[j] = bl.open & movemask(ta <= tb);
    }
    for (uint32_t k = 0; k < count && (blocks & ~done); ++k) {
        const uint32_t id = ids[k];
        const TriangleVerts& tri = triangles[id];
        // As intersect_watertight's first step: v - org per component, then permuted.
        const Vec3f a = tri.v0 - light, b = tri.v1 - light, c = tri.v2 - light;
        int perm = -1;
        const vf zero(0.f);
        RelativeTriangle<K> rel{zero, zero, zero, zero, zero, zero, zero, zero, zero};
        for (uint32_t m = blocks & ~done; m; m &= m - 1) {
            const int j = std::countr_zero(m);
            Block& bl = block[j];
            const uint32_t lanes = lane_mask[j];
            if (!lanes) continue;
            const WatertightPacket<K>& wp = bl.wp;
            vf t;
            vb hit;
            if (wp.uniform) [[likely]] {
                const int p = wp.ukx | wp.uky << 2 | wp.ukz << 4;
                if (p != perm) {
                    perm = p;
                    rel = RelativeTriangle<K>{
                        vf(coord(a, wp.ukx)), vf(coord(a, wp.uky)), vf(coord(a, wp.ukz)),
                        vf(coord(b, wp.ukx)), vf(coord(b, wp.uky)), vf(coord(b, wp.ukz)),
                        vf(coord(c, wp.ukx)), vf(coord(c, wp.uky)), vf(coord(c, wp.ukz))};
                }
                hit = intersect_watertight_relative<K, true>(wp, vb::from_bits(lanes), rel, t);
            } else {
                hit = intersect_watertight<K, true>(wp, vb::from_bits(lanes), tri, t);
            }
            const uint32_t h = movemask(hit);
            if (!h) continue;
            bl.open &= ~h;
            lane_mask[j] &= ~h;
            if (!bl.open) done |= 1u << j;
        }
    }
}

/// Traverses the tree once for all blocks of the chunk, the light's side of each split first.
void traverse(const KdTree& tree, std::span<const TriangleVerts> triangles, const Frusta& f,
              const Bbox3f& root, Block* block) {
    Entry stack[kd_max_depth + 1];
    int top = 0;
    Entry e{tree.nodes.data(), {root.lo.x, root.lo.y, root.lo.z}, {root.hi.x, root.hi.y, root.hi.z},
            0};
    e.blocks = f.enter(e.lo, e.hi);
    if (e.blocks) stack[top++] = e;
    const KdNode* nodes = tree.nodes.data();
    uint32_t done = 0;  // blocks whose every segment is occluded
    while (top > 0) {
        e = stack[--top];
        e.blocks &= ~done;
        if (!e.blocks) continue;
        const KdNode* node = e.node;
        while (!node->is_leaf()) {
            const int a = node->axis();
            const float s = node->split;
            const float lo = e.lo[a], hi = e.hi[a];
            e.hi[a] = s;
            const uint32_t in_below = f.enter(e.lo, e.hi) & e.blocks;
            e.hi[a] = hi;
            e.lo[a] = s;
            const uint32_t in_above = f.enter(e.lo, e.hi) & e.blocks;
            e.lo[a] = lo;
            const bool below_first = !(f.light[a] > s);
            const KdNode* below = node + 1;
            const KdNode* above = nodes + node->above_child();
            const uint32_t in_near = below_first ? in_below : in_above;
            const uint32_t in_far = below_first ? in_above : in_below;
            if (in_far) {
                if (!in_near) {
                    node = below_first ? above : below;
                    e.blocks = in_far;
                    (below_first ? e.lo : e.hi)[a] = s;
                    continue;
                }
                Entry& p = stack[top++];
                p = e;
                p.node = below_first ? above : below;
                p.blocks = in_far;
                (below_first ? p.lo : p.hi)[a] = s;
            }
            if (!in_near) break;
            node = below_first ? below : above;
            e.blocks = in_near;
            (below_first ? e.hi : e.lo)[a] = s;
        }
        if (node->is_leaf()) visit_leaf(tree, triangles, *node, e.lo, e.hi, e.blocks, f.light, block, done);
    }
}

}  // namespace

uint64_t occluded_frustum(const KdTree& tree, std::span<const TriangleVerts> triangles,
                          const SegmentTile& tile, std::span<uint8_t> visible) {
    const Vec3f light = tile.light;
    const bool finite = std::isfinite(light.x) && std::isfinite(light.y) && std::isfinite(light.z);
    if (tree.nodes.empty() || !finite)
        return occluded_tile_packets<K>(tree, triangles, tile, visible);
    for (uint8_t& v : visible) v = 0;

    const Bbox3f root = padded_bounds(tree.bounds);
    // D: the largest coordinate distance from the light to the padded bounds. Every segment
    // point trace_ray can place in a node lies within 2^-15 D (margins) of its cell, and
    // evaluating a plane of slope <= 4 at a cell corner errs by < 2^-20 D; slack = 2^-9 D.
    float D = 0.f;
    for (int a = 0; a < 3; ++a)
        D = std::max({D, std::fabs(root.lo[a] - light[a]), std::fabs(root.hi[a] - light[a])});

    const int width = tile.width, height = tile.height;
    uint64_t count = 0;
    Block block[K];
    RayPacket<K> packet[K];
    for (int cy = 0; cy < height; cy += ch * ph) {
        for (int cx = 0; cx < width; cx += cw * pw) {
            // The chunk's blocks as packets, as occluded_tile_packets stages them.
            uint32_t live = 0;
            for (int j = 0; j < K; ++j) {
                const int x0 = cx + (j % cw) * pw, y0 = cy + (j / cw) * ph;
                uint32_t in = 0;
                int first = -1;
                for (int l = 0; l < K; ++l) {
                    const int x = x0 + l % pw, y = y0 + l / pw;
                    if (x < width && y < height && tile.active[size_t(y * width + x)]) {
                        in |= 1u << l;
                        if (first < 0) first = y * width + x;
                    }
                }
                block[j].in = block[j].open = in;
                if (!in) continue;
                live |= 1u << j;
                count += uint64_t(std::popcount(in));
                if (x0 + pw <= width && y0 + ph <= height) {
                    load_segment_packet<K>(light, tile.points.data() + y0 * width + x0, width, in,
                                           packet[j]);
                } else {
                    for (int l = 0; l < K; ++l) {
                        const int x = x0 + l % pw, y = y0 + l / pw;
                        const int s = (in >> l) & 1u ? y * width + x : first;
                        packet[j].set(l, shadow_ray(light, tile.points[size_t(s)]));
                    }
                }
            }
            if (!live) continue;

            // The frame: the dominant axis of the chunk's first segment.
            Frusta f;
            f.light = light;
            f.live = live;
            f.slack = 0x1p-9f * D;
            {
                const RayPacket<K>& p = packet[std::countr_zero(live)];
                const int l = std::countr_zero(block[std::countr_zero(live)].in);
                const Vec3f w{p.dir[0][l], p.dir[1][l], p.dir[2][l]};
                f.kz = max_abs_axis(w);
                f.kx = (f.kz + 1) % 3;
                f.ky = (f.kz + 2) % 3;
                f.sigma = w[f.kz] < 0.f ? -1.f : 1.f;
            }
            alignas(64) float umin[K], umax[K], vmin[K], vmax[K], far[K];
            uint32_t outside = 0;
            for (int j = 0; j < K; ++j) {
                umin[j] = umax[j] = vmin[j] = vmax[j] = far[j] = 0.f;  // not live: never asked
                const uint32_t in = block[j].in;
                if (!in) continue;
                const RayPacket<K>& p = packet[j];
                const Vec3v<K> w{vf::load(p.dir[0]), vf::load(p.dir[1]), vf::load(p.dir[2])};
                const vb lanes = vb::from_bits(in);
                block[j].wp = WatertightPacket<K>(Vec3v<K>(light), w, vf::load(p.tmin),
                                                  vf::load(p.tmax), lanes);
                const vf org[3] = {vf(light.x), vf(light.y), vf(light.z)};
                for (int a = 0; a < 3; ++a) block[j].inv[a] = rcp(w[a]);
                clip_to_root<K>(root, org, w, block[j].inv, vf::load(p.tmin), vf::load(p.tmax),
                                block[j].t0, block[j].t1, block[j].t_scale);
                vf u, v;
                outside |= out_of_frame(f, w, in, u, v);
                umin[j] = reduce_min(select(lanes, u, vf(pos_inf)))[0];
                umax[j] = reduce_max(select(lanes, u, vf(neg_inf)))[0];
                vmin[j] = reduce_min(select(lanes, v, vf(pos_inf)))[0];
                vmax[j] = reduce_max(select(lanes, v, vf(neg_inf)))[0];
                far[j] = reduce_max(select(lanes, w[f.kz] * vf(f.sigma), vf(neg_inf)))[0];
            }
            if (outside) {
                // Some segment leaves the frame: the chunk goes to the packets.
                for (uint32_t m = live; m; m &= m - 1) {
                    const int j = std::countr_zero(m);
                    block[j].open &= ~occluded_packet<K>(tree, triangles, packet[j], block[j].in);
                }
            } else {
                f.umin = widen_down(vf::load(umin));
                f.umax = widen_up(vf::load(umax));
                f.vmin = widen_down(vf::load(vmin));
                f.vmax = widen_up(vf::load(vmax));
                f.far = vf::load(far);
                traverse(tree, triangles, f, root, block);
            }
            for (uint32_t m = live; m; m &= m - 1) {
                const int j = std::countr_zero(m);
                const int x0 = cx + (j % cw) * pw, y0 = cy + (j / cw) * ph;
                for (uint32_t l = block[j].in; l; l &= l - 1) {
                    const int lane = std::countr_zero(l);
                    visible[size_t((y0 + lane / pw) * width + x0 + lane % pw)] =
                        (block[j].open >> lane) & 1u;
                }
            }
        }
    }
    return count;
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
