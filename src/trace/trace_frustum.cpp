#include "trace/trace_frustum.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <vector>

#include "geom/triangle_simd.h"
#include "simd/simd.h"
#include "trace/factories.h"
#include "trace/root_clip.h"
#include "trace/trace_packet.h"
#include "trace/trace_ray.h"
#include "trace/traced_tile.h"

namespace rtt {
namespace {

constexpr int K = simd_max_width;
using vf = vfloat<K>;
using vb = vbool<K>;

/// K rays of one octant of the packet, with all their leaves need: the watertight constants
/// (tmax shrinks to the closest hit, inclusive), the closest hits, and what re-derives the rays'
/// node intervals (inverse directions, root interval, t_scale, as trace_ray computes them).
struct alignas(64) Block {
    WatertightPacket<K> wp;
    PacketHit<K> best;
    vf inv[3];
    vf t0, t1, t_scale;
    uint32_t valid = 0;        ///< Lanes with a ray whose root interval is not empty.
    float max_best = pos_inf;  ///< Largest best t of the valid lanes.
    int sample[K];             ///< The ray of each lane (-1: none).
};

/// The packet's bounds over its valid rays, the scalar side of the traversal.
struct PacketBounds {
    float inv_lo[3], inv_hi[3];  ///< Smallest and largest inverse direction per axis.
    float t_scale = 0.f;         ///< Largest t_scale.
    float ta = pos_inf, tb = neg_inf;
};

void init_block(Block& b, std::span<const Ray> rays, const int* samples, int count,
                const Bbox3f& box) {
    alignas(64) float d[3][K], tmin[K], tmax[K];
    for (int l = 0; l < K; ++l) {
        // Lanes past the group's end copy its first ray: finite, as the watertight test asks.
        const Ray& r = rays[size_t(samples[l < count ? l : 0])];
        for (int a = 0; a < 3; ++a) d[a][l] = r.dir[a];
        tmin[l] = r.tmin;
        tmax[l] = r.tmax;
        b.sample[l] = l < count ? samples[l] : -1;
    }
    const Vec3f o = rays[size_t(samples[0])].org;
    const vf org[3] = {vf(o.x), vf(o.y), vf(o.z)};
    const Vec3v<K> dir{vf::load(d[0]), vf::load(d[1]), vf::load(d[2])};
    for (int a = 0; a < 3; ++a) b.inv[a] = rcp(dir[a]);
    const vf lo = vf::load(tmin), hi = vf::load(tmax);
    clip_to_root<K>(box, org, dir, b.inv, lo, hi, b.t0, b.t1, b.t_scale);
    const uint32_t in = count >= K ? all_lanes<K> : (1u << count) - 1u;
    b.valid = movemask(b.t0 <= b.t1) & in;
    b.wp = WatertightPacket<K>(Vec3v<K>(o), dir, lo, hi, vb::from_bits(in));
    b.best = PacketHit<K>{};
    b.max_best = pos_inf;
}

/// One deferred subtree: its node, the packet's scalar interval there, the node's cell (the
/// split planes around it; +-inf where none) and the range of blocks that still take part.
struct Entry {
    const KdNode* node;
    float ta, tb;
    float lo[3], hi[3];
    int first, last;
};

/// Each block's lanes that may find their answer in the leaf: trace_ray's interval of each
/// ray, re-derived from the leaf's nearest faces only (a superset: trace_ray takes the max and
/// min over every ancestor split, these faces among them), not empty and starting no later
/// than the ray's closest hit. Then the leaf's triangles, K lanes at a time.
RTT_FORCEINLINE void visit_leaf(const KdNode& leaf, const Entry& e, const Vec3f& org, uint32_t neg,
                                const KdTree& tree, std::span<const TriangleVerts> triangles,
                                Block* blocks) {
    const uint32_t count = leaf.triangle_count();
    if (count == 0) return;
    const uint32_t* ids = tree.leaf_triangles.data() + leaf.first_triangle();
    // Per axis the face a ray of this octant enters by, and the one it leaves by.
    float enter[3], leave[3];
    bool has_enter[3], has_leave[3];
    for (int a = 0; a < 3; ++a) {
        const bool down = (neg >> a) & 1u;
        const float in = down ? e.hi[a] : e.lo[a], out = down ? e.lo[a] : e.hi[a];
        has_enter[a] = std::isfinite(in);
        has_leave[a] = std::isfinite(out);
        enter[a] = in - org[a];  // (split - org[axis]) as trace_ray computes it
        leave[a] = out - org[a];
    }
    const vf margin(kd_margin);
    for (int bi = e.first; bi <= e.last; ++bi) {
        Block& b = blocks[bi];
        if (!b.valid || b.max_best < e.ta) continue;
        vf ta = b.t0, tb = b.t1;
        for (int a = 0; a < 3; ++a) {
            // A NaN d (0 * inf) or an inf - inf margin leaves the bound as it was (min and max
            // return their second operand): wider than trace_ray's, never narrower.
            if (has_enter[a]) {
                const vf d = vf(enter[a]) * b.inv[a];
                ta = max(d - (abs(d) + b.t_scale) * margin, ta);
            }
            if (has_leave[a]) {
                const vf d = vf(leave[a]) * b.inv[a];
                tb = min(d + (abs(d) + b.t_scale) * margin, tb);
            }
        }
        const vb lanes = vb::from_bits(b.valid) & (ta <= tb) & (ta <= b.best.t);
        if (none(lanes)) continue;
        for (uint32_t k = 0; k < count; ++k) {
            const uint32_t id = ids[k];
            vf t;
            const vb hit = intersect_watertight<K, true>(b.wp, lanes, triangles[id], t);
            if (none(hit)) continue;
            // inclusive tmax: a later equal-t hit still reaches the index tie-break
            b.wp.tmax = select(b.best.update(hit, t, id), t, b.wp.tmax);
        }
        b.max_best = reduce_max(select(vb::from_bits(b.valid), b.best.t, vf(neg_inf)))[0];
    }
}

/// Traverses the tree with the blocks of one octant (direction sign bits `neg`, bit a = axis
/// a), all from `org`. See trace_frustum.h for why every ray gets trace_ray's answer.
void traverse_group(const KdTree& tree, std::span<const TriangleVerts> triangles,
                    const Vec3f& org, uint32_t neg, Block* blocks, int nblocks) {
    PacketBounds p;
    for (int a = 0; a < 3; ++a) {
        p.inv_lo[a] = pos_inf;
        p.inv_hi[a] = neg_inf;
    }
    int first = nblocks, last = -1;
    for (int i = 0; i < nblocks; ++i) {
        const Block& b = blocks[i];
        if (!b.valid) continue;
        first = std::min(first, i);
        last = i;
        const vb v = vb::from_bits(b.valid);
        // inv is +-inf for a zero component, never NaN; t0, t1, t_scale are NaN-free.
        for (int a = 0; a < 3; ++a) {
            p.inv_lo[a] = std::min(p.inv_lo[a], reduce_min(select(v, b.inv[a], vf(pos_inf)))[0]);
            p.inv_hi[a] = std::max(p.inv_hi[a], reduce_max(select(v, b.inv[a], vf(neg_inf)))[0]);
        }
        p.t_scale = std::max(p.t_scale, reduce_max(select(v, b.t_scale, vf(0.f)))[0]);
        p.ta = std::min(p.ta, reduce_min(select(v, b.t0, vf(pos_inf)))[0]);
        p.tb = std::max(p.tb, reduce_max(select(v, b.t1, vf(neg_inf)))[0]);
    }
    if (first > last) return;

    Entry stack[kd_max_depth + 1];
    int top = 0;
    stack[top++] = Entry{tree.nodes.data(), p.ta, p.tb, {neg_inf, neg_inf, neg_inf},
                         {pos_inf, pos_inf, pos_inf}, first, last};
    const KdNode* nodes = tree.nodes.data();
    while (top > 0) {
        Entry e = stack[--top];
        // Blocks whose every ray has a hit before the node's start (e.ta <= each ray's start)
        // skip it; the range shrinks from both ends.
        const auto done = [&](int i) { return !blocks[i].valid || blocks[i].max_best < e.ta; };
        while (e.first <= e.last && done(e.first)) ++e.first;
        while (e.last >= e.first && done(e.last)) --e.last;
        if (e.first > e.last) continue;
        // No ray needs the node past its closest hit: the frustum's far end shrinks with hits.
        float far = neg_inf;
        for (int i = e.first; i <= e.last; ++i)
            if (blocks[i].valid) far = std::max(far, blocks[i].max_best);
        if (far < e.tb) e.tb = far;
        if (e.ta > e.tb) continue;

        const KdNode* node = e.node;
        while (!node->is_leaf()) {
            const KdNode& n = *node;
            const int axis = n.axis();
            const bool down = (neg >> axis) & 1u;  // the rays meet `above` first
            const KdNode* below = node + 1;
            const KdNode* above = nodes + n.above_child();
            // Every ray's d = D * inv lies between the products with the extreme inverses
            // (rounding is monotone), and its margin below the one from the largest |d|.
            const float D = n.split - org[axis];
            const float da = D * p.inv_lo[axis], db = D * p.inv_hi[axis];
            bool visit_first = true, visit_second = true;
            float first_tb = e.tb, second_ta = e.ta;
            if (!std::isnan(da) && !std::isnan(db)) {
                const float m = (std::max(std::fabs(da), std::fabs(db)) + p.t_scale) * kd_margin;
                const float up = std::max(da, db) + m, low = std::min(da, db) - m;
                // NaN (inf - inf) visits and leaves the bound as it was.
                visit_first = !(e.ta > up);
                visit_second = !(low > e.tb);
                if (up < e.tb) first_tb = up;
                if (low > e.ta) second_ta = low;
            }
            const KdNode* first_child = down ? above : below;
            const KdNode* second_child = down ? below : above;
            if (visit_second) {
                if (!visit_first) {
                    node = second_child;
                    e.ta = second_ta;
                    (down ? e.hi : e.lo)[axis] = n.split;
                    continue;
                }
                Entry& s = stack[top++];
                s = e;
                s.node = second_child;
                s.ta = second_ta;
                (down ? s.hi : s.lo)[axis] = n.split;
            }
            // visit_first (one of the two always holds while e.ta <= e.tb)
            node = first_child;
            e.tb = first_tb;
            (down ? e.lo : e.hi)[axis] = n.split;
        }
        visit_leaf(*node, e, org, neg, tree, triangles, blocks);
    }
}

/// Scratch of one thread: the blocks of the current tile and the sample order.
struct Scratch {
    std::vector<Block> blocks;
    std::vector<int> order, grouped;
};

}  // namespace

bool share_origin(std::span<const Ray> rays) {
    if (rays.empty()) return false;
    const Vec3f o = rays[0].org;
    for (const Ray& r : rays)
        if (std::memcmp(&r.org, &o, sizeof(Vec3f)) != 0) return false;
    return true;
}

void trace_frustum(const KdTree& tree, std::span<const TriangleVerts> triangles,
                   std::span<const Ray> rays, int width, int height, std::span<Hit> hits) {
    for (Hit& h : hits) h = Hit{};
    if (tree.nodes.empty() || rays.empty()) return;
    thread_local Scratch s;
    // Samples in packet-shaped blocks of the grid (packet_width x packet_height), so that the K
    // lanes of a block are neighbours; then grouped by octant, keeping that order.
    constexpr int pw = packet_width<K>, ph = packet_height<K>;
    s.order.clear();
    for (int y0 = 0; y0 < height; y0 += ph)
        for (int x0 = 0; x0 < width; x0 += pw)
            for (int y = y0; y < std::min(y0 + ph, height); ++y)
                for (int x = x0; x < std::min(x0 + pw, width); ++x) s.order.push_back(y * width + x);
    const auto octant = [&](int i) {
        const Vec3f& d = rays[size_t(i)].dir;
        return uint32_t(std::signbit(d.x)) | uint32_t(std::signbit(d.y)) << 1 |
               uint32_t(std::signbit(d.z)) << 2;
    };
    int start[9] = {};
    for (int i : s.order) ++start[octant(i) + 1];
    for (int o = 0; o < 8; ++o) start[o + 1] += start[o];
    s.grouped.resize(s.order.size());
    int fill[8];
    std::copy(start, start + 8, fill);
    for (int i : s.order) s.grouped[size_t(fill[octant(i)]++)] = i;

    const Bbox3f box = padded_bounds(tree.bounds);
    const Vec3f org = rays[0].org;
    for (uint32_t o = 0; o < 8; ++o) {
        const int n = start[o + 1] - start[o];
        if (n == 0) continue;
        const int nblocks = (n + K - 1) / K;
        s.blocks.resize(size_t(nblocks));
        for (int b = 0; b < nblocks; ++b)
            init_block(s.blocks[size_t(b)], rays, s.grouped.data() + start[o] + b * K,
                       std::min(K, n - b * K), box);
        traverse_group(tree, triangles, org, o, s.blocks.data(), nblocks);
        for (const Block& b : s.blocks)
            for (int l = 0; l < K; ++l)
                if (b.sample[l] >= 0)
                    hits[size_t(b.sample[l])] = Hit{b.best.t[l], uint32_t(b.best.tri[l])};
    }
}

namespace {

/// The "frustum" kind: shaft tiles whose rays share an origin as one large packet
/// (trace_frustum); everything else through the widest packets, as RTT's fallback.
class FrustumTracer final : public Tracer {
public:
    FrustumTracer(const Scene& scene, const KdTree& tree)
        : tree_(tree), triangles_(gather_triangles(scene)) {}
    std::string_view name() const override { return "frustum"; }

    void intersect(const RayTile& tile, std::span<Hit> hits, TraceStats* stats,
                   std::span<SampleAnswer> answers) const override {
        if (tile.shaft && share_origin(tile.rays))
            trace_frustum(tree_, triangles_, tile.rays, tile.width, tile.height, hits);
        else
            trace_tile_packets<K>(tree_, triangles_, tile, hits);
        record_traced_tile(tile.rays.size(), stats, answers);
    }

    void occluded(const SegmentTile& tile, std::span<uint8_t> visible, TraceStats* stats,
                  std::span<SampleAnswer> answers) const override {
        const uint64_t n = occluded_tile_packets<K>(tree_, triangles_, tile, visible);
        record_traced_tile(n, stats, answers);
    }

private:
    const KdTree& tree_;
    std::vector<TriangleVerts> triangles_;
};

}  // namespace

std::unique_ptr<Tracer> make_frustum_tracer(const Scene& scene, const KdTree& tree) {
    return std::make_unique<FrustumTracer>(scene, tree);
}

}  // namespace rtt
