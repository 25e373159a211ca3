#include "trace/trace_frustum.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <vector>

#include "geom/triangle_simd.h"
#include "simd/simd.h"
#include "trace/octant_groups.h"
#include "trace/root_clip.h"
#include "trace/trace_packet.h"
#include "trace/trace_ray.h"

namespace rtt {
inline namespace RTT_ISA_NS {
namespace {

constexpr int K = simd_max_width;
constexpr int pw = packet_width<K>, ph = packet_height<K>;
using vf = vfloat<K>;
using vb = vbool<K>;
static_assert(sizeof(Ray) == 8 * sizeof(float) && sizeof(Hit) == 2 * sizeof(float));

/// K rays of one octant from a packet_width x packet_height square of the grid, with all their
/// leaves need: the watertight constants (tmax shrinks to the closest hit, inclusive), the
/// closest hits, and what re-derives the rays' node intervals (inverse directions, root
/// interval, t_scale, as trace_ray computes them).
struct alignas(64) Block {
    WatertightPacket<K> wp;
    PacketHit<K> best;
    vf inv[3];
    vf t0, t1, t_scale;
    uint32_t in = 0;     ///< Lanes of this octant inside the grid.
    uint32_t valid = 0;  ///< Of those, the lanes whose root interval is not empty.
    int sample = 0;      ///< Sample of lane 0; lane l is sample + (l / pw) * width + l % pw.
};

/// Per block, bounds over its valid rays, as arrays over blocks (K blocks to a vector): what a
/// leaf needs to drop a whole block with one lane of arithmetic (visit_leaf).
struct BlockBounds {
    enum { inv_lo = 0, inv_hi = 3, t_scale = 6, ta = 7, tb = 8, max_best = 9, count = 10 };
    std::vector<vf> field[count];

    float* operator[](int f) { return reinterpret_cast<float*>(field[f].data()); }
    void reset(int nblocks) {
        // Padding and empty blocks never pass: ta = +inf > tb = -inf, max_best = -inf.
        for (int f = 0; f < count; ++f)
            field[f].assign(size_t((nblocks + K - 1) / K),
                            vf(f == tb || f == max_best ? neg_inf : pos_inf));
    }
};

/// The rays of the grid square with top-left sample (x0, y0) as vectors (org xyz, dir xyz,
/// tmin, tmax); returns the lanes inside the grid (the others copy the square's first ray).
RTT_FORCEINLINE uint32_t load_square(std::span<const Ray> rays, int width, int height, int x0,
                                     int y0, vf (&f)[8]) {
    if (x0 + pw <= width && y0 + ph <= height) {
        load_record_rows8(reinterpret_cast<const float*>(rays.data() + y0 * width + x0),
                          std::ptrdiff_t(8) * width, f);
        return all_lanes<K>;
    }
    alignas(64) float lanes[8][K];
    uint32_t in = 0;
    for (int l = 0; l < K; ++l) {
        const int x = x0 + l % pw, y = y0 + l / pw;
        const bool inside = x < width && y < height;
        in |= uint32_t(inside) << l;
        const float* r =
            reinterpret_cast<const float*>(&rays[size_t(inside ? y * width + x : y0 * width + x0)]);
        for (int k = 0; k < 8; ++k) lanes[k][l] = r[k];
    }
    for (int k = 0; k < 8; ++k) f[k] = vf::load(lanes[k]);
    return in;
}

/// Block `i` from the lanes `in` of a loaded square, and its bounds.
void init_block(Block& b, BlockBounds& bounds, int i, const vf (&f)[8], uint32_t in, int sample,
                const Bbox3f& box) {
    const vf org[3] = {f[0], f[1], f[2]};
    const Vec3v<K> dir{f[3], f[4], f[5]};
    for (int a = 0; a < 3; ++a) b.inv[a] = rcp(dir[a]);
    clip_to_root<K>(box, org, dir, b.inv, f[6], f[7], b.t0, b.t1, b.t_scale);
    b.in = in;
    b.valid = movemask(b.t0 <= b.t1) & in;
    b.sample = sample;
    b.wp =
        WatertightPacket<K>(Vec3v<K>{org[0], org[1], org[2]}, dir, f[6], f[7], vb::from_bits(in));
    b.best = PacketHit<K>{};
    if (!b.valid) return;  // the padding values never pass
    // inv is +-inf for a zero component, never NaN; t0, t1, t_scale are NaN-free.
    const vb v = vb::from_bits(b.valid);
    for (int a = 0; a < 3; ++a) {
        bounds[BlockBounds::inv_lo + a][i] = reduce_min(select(v, b.inv[a], vf(pos_inf)))[0];
        bounds[BlockBounds::inv_hi + a][i] = reduce_max(select(v, b.inv[a], vf(neg_inf)))[0];
    }
    bounds[BlockBounds::t_scale][i] = reduce_max(select(v, b.t_scale, vf(0.f)))[0];
    bounds[BlockBounds::ta][i] = reduce_min(select(v, b.t0, vf(pos_inf)))[0];
    bounds[BlockBounds::tb][i] = reduce_max(select(v, b.t1, vf(neg_inf)))[0];
    bounds[BlockBounds::max_best][i] = pos_inf;
}

/// One deferred subtree: its node, the packet's scalar interval there, the node's cell (the
/// split planes around it; +-inf where none) and the range of blocks that still take part.
struct Entry {
    const KdNode* node;
    float ta, tb;
    float lo[3], hi[3];
    int first, last;
};

/// A bound on the node intervals of a set of rays from one origin: their split distances
/// d = D * inv lie between D * inv_lo and D * inv_hi (float rounding is monotone), their
/// margins below the one of the larger |d| with the largest t_scale. `low` bounds d - m from
/// below, `up` bounds d + m from above; `nan`: some ray's d may be NaN (0 * inf), so neither
/// bounds anything (trace_ray then keeps the interval, as callers do).
template <typename F>
struct SplitBound {
    F low, up;
    decltype(F() != F()) nan;

    RTT_FORCEINLINE SplitBound(F D, F inv_lo, F inv_hi, F t_scale) {
        const F da = D * inv_lo, db = D * inv_hi;
        nan = (da != da) | (db != db);
        using std::abs, std::max, std::min;
        const F m = (max(abs(da), abs(db)) + t_scale) * F(kd_margin);
        low = min(da, db) - m;  // NaN when inf - inf: callers keep their bound then
        up = max(da, db) + m;
    }
};

/// The leaf's triangles for the rays that may find their answer in it. A ray takes part when
/// trace_ray's interval there, re-derived from the leaf's nearest faces only (a superset:
/// trace_ray takes the max and min over every ancestor split, these faces among them), is not
/// empty and starts no later than the ray's closest hit so far. Blocks are first dropped whole
/// with their bounds (K blocks at a time), then lane by lane.
RTT_FORCEINLINE void visit_leaf(const KdNode& leaf, const Entry& e, const Vec3f& org, uint32_t neg,
                                const KdTree& tree, std::span<const TriangleVerts> triangles,
                                Block* blocks, BlockBounds& bounds) {
    const uint32_t count = leaf.triangle_count();
    if (count == 0) return;
    const uint32_t* ids = tree.leaf_triangles.data() + leaf.first_triangle();
    // The triangles' loads start while the blocks' bounds are computed.
    for (uint32_t k = 0; k < count; ++k) __builtin_prefetch(&triangles[ids[k]]);
    // Per axis the face a ray of this octant enters by, and the one it leaves by, as
    // (split - org[axis]), which trace_ray computes first.
    float enter[3], leave[3];
    bool has_enter[3], has_leave[3];
    for (int a = 0; a < 3; ++a) {
        const bool down = (neg >> a) & 1u;
        const float in = down ? e.hi[a] : e.lo[a], out = down ? e.lo[a] : e.hi[a];
        has_enter[a] = std::isfinite(in);
        has_leave[a] = std::isfinite(out);
        enter[a] = in - org[a];
        leave[a] = out - org[a];
    }
    const vf margin(kd_margin);
    for (int c = e.first / K; c <= e.last / K; ++c) {
        const auto load = [&](int f) { return vf::load(bounds[f] + c * K); };
        vf ta = load(BlockBounds::ta), tb = load(BlockBounds::tb);
        for (int a = 0; a < 3; ++a) {
            if (!has_enter[a] && !has_leave[a]) continue;
            const vf lo = load(BlockBounds::inv_lo + a), hi = load(BlockBounds::inv_hi + a);
            const vf ts = load(BlockBounds::t_scale);
            if (has_enter[a]) {
                const SplitBound<vf> s(vf(enter[a]), lo, hi, ts);
                ta = max(select(s.nan, vf(neg_inf), s.low), ta);
            }
            if (has_leave[a]) {
                const SplitBound<vf> s(vf(leave[a]), lo, hi, ts);
                tb = min(select(s.nan, vf(pos_inf), s.up), tb);
            }
        }
        uint32_t pass = movemask((ta <= tb) & (ta <= load(BlockBounds::max_best)));
        const int lo_bit = std::max(e.first - c * K, 0), hi_bit = std::min(e.last - c * K, K - 1);
        pass &= (all_lanes<K> >> (K - 1 - hi_bit)) & ~((1u << lo_bit) - 1u);
        for (; pass; pass &= pass - 1) {
            const int bi = c * K + std::countr_zero(pass);
            Block& b = blocks[bi];
            vf lta = b.t0, ltb = b.t1;
            for (int a = 0; a < 3; ++a) {
                // A NaN d (0 * inf) or an inf - inf margin leaves the bound as it was (min and
                // max return their second operand): wider than trace_ray's, never narrower.
                if (has_enter[a]) {
                    const vf d = vf(enter[a]) * b.inv[a];
                    lta = max(d - (abs(d) + b.t_scale) * margin, lta);
                }
                if (has_leave[a]) {
                    const vf d = vf(leave[a]) * b.inv[a];
                    ltb = min(d + (abs(d) + b.t_scale) * margin, ltb);
                }
            }
            const vb lanes = vb::from_bits(b.valid) & (lta <= ltb) & (lta <= b.best.t);
            if (none(lanes)) continue;
            for (uint32_t k = 0; k < count; ++k) {
                const uint32_t id = ids[k];
                vf t;
                const vb hit = intersect_watertight<K, true>(b.wp, lanes, triangles[id], t);
                if (none(hit)) continue;
                // inclusive tmax: a later equal-t hit still reaches the index tie-break
                b.wp.tmax = select(b.best.update(hit, t, id), t, b.wp.tmax);
            }
            bounds[BlockBounds::max_best][bi] =
                reduce_max(select(vb::from_bits(b.valid), b.best.t, vf(neg_inf)))[0];
        }
    }
}

/// Traverses the tree with the blocks of one octant (direction sign bits `neg`, bit a = axis
/// a), all from `org`. See trace_frustum.h for why every ray gets trace_ray's answer.
void traverse_group(const KdTree& tree, std::span<const TriangleVerts> triangles, const Vec3f& org,
                    uint32_t neg, Block* blocks, BlockBounds& bounds, int nblocks) {
    // The packet's bounds: the blocks' bounds over its valid blocks.
    float inv_lo[3] = {pos_inf, pos_inf, pos_inf}, inv_hi[3] = {neg_inf, neg_inf, neg_inf};
    float t_scale = 0.f, ta = pos_inf, tb = neg_inf;
    int first = nblocks, last = -1;
    for (int i = 0; i < nblocks; ++i) {
        if (!blocks[i].valid) continue;
        first = std::min(first, i);
        last = i;
        for (int a = 0; a < 3; ++a) {
            inv_lo[a] = std::min(inv_lo[a], bounds[BlockBounds::inv_lo + a][i]);
            inv_hi[a] = std::max(inv_hi[a], bounds[BlockBounds::inv_hi + a][i]);
        }
        t_scale = std::max(t_scale, bounds[BlockBounds::t_scale][i]);
        ta = std::min(ta, bounds[BlockBounds::ta][i]);
        tb = std::max(tb, bounds[BlockBounds::tb][i]);
    }
    if (first > last) return;

    Entry stack[kd_max_depth + 1];
    int top = 0;
    stack[top++] = Entry{tree.nodes.data(),           ta,    tb,  {neg_inf, neg_inf, neg_inf},
                         {pos_inf, pos_inf, pos_inf}, first, last};
    const KdNode* nodes = tree.nodes.data();
    const float* max_best = bounds[BlockBounds::max_best];
    while (top > 0) {
        Entry e = stack[--top];
        // Blocks whose every ray has a hit before the node's start (e.ta <= each ray's start)
        // skip it; the range shrinks from both ends.
        // (An empty block's max_best is -inf: BlockBounds::reset; read from the compact array,
        // not from the blocks, 1.5 KB apart.)
        const auto done = [&](int i) { return max_best[i] < e.ta; };
        while (e.first <= e.last && done(e.first)) ++e.first;
        while (e.last >= e.first && done(e.last)) --e.last;
        if (e.first > e.last) continue;
        // No ray needs the node past its closest hit: the frustum's far end shrinks with hits.
        float far = neg_inf;
        for (int i = e.first; i <= e.last; ++i) far = std::max(far, max_best[i]);
        if (far < e.tb) e.tb = far;
        if (e.ta > e.tb) continue;

        const KdNode* node = e.node;
        while (!node->is_leaf()) {
            const KdNode& n = *node;
            const int axis = n.axis();
            const bool down = (neg >> axis) & 1u;  // the rays meet `above` first
            const KdNode* below = node + 1;
            const KdNode* above = nodes + n.above_child();
            const SplitBound<float> s(n.split - org[axis], inv_lo[axis], inv_hi[axis], t_scale);
            bool visit_first = true, visit_second = true;
            float first_tb = e.tb, second_ta = e.ta;
            if (!s.nan) {
                // A NaN bound (inf - inf) visits and leaves the interval as it was.
                visit_first = !(e.ta > s.up);
                visit_second = !(s.low > e.tb);
                if (s.up < e.tb) first_tb = s.up;
                if (s.low > e.ta) second_ta = s.low;
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
                Entry& p = stack[top++];
                p = e;
                p.node = second_child;
                p.ta = second_ta;
                (down ? p.hi : p.lo)[axis] = n.split;
            }
            // visit_first (one of the two always holds while e.ta <= e.tb)
            node = first_child;
            e.tb = first_tb;
            (down ? e.lo : e.hi)[axis] = n.split;
        }
        visit_leaf(*node, e, org, neg, tree, triangles, blocks, bounds);
    }
}

/// The part of a grid square in one octant.
struct Part {
    int x0, y0;
    uint32_t lanes;
};

/// Scratch of one thread: the current tile's parts by octant, blocks and bounds.
struct Scratch {
    std::vector<Part> parts[8];
    std::vector<Block> blocks;
    BlockBounds bounds;
};

}  // namespace

bool trace_frustum(const KdTree& tree, std::span<const TriangleVerts> triangles,
                   std::span<const Ray> rays, int width, int height, std::span<Hit> hits) {
    if (rays.empty()) return true;
    thread_local Scratch s;
    // The grid in packet-shaped squares, so that the K lanes of a block are neighbours; each
    // square's lanes split by the octant of their direction. Refused (false) at once when some
    // ray has another origin.
    const Vec3f org = rays[0].org;
    const vint<K> ox(std::bit_cast<int32_t>(org.x)), oy(std::bit_cast<int32_t>(org.y)),
        oz(std::bit_cast<int32_t>(org.z));
    for (auto& p : s.parts) p.clear();
    for (int y0 = 0; y0 < height; y0 += ph)
        for (int x0 = 0; x0 < width; x0 += pw) {
            vf f[8];
            const uint32_t in = load_square(rays, width, height, x0, y0, f);
            const vb same = (as_int(f[0]) == ox) & (as_int(f[1]) == oy) & (as_int(f[2]) == oz);
            if ((movemask(same) & in) != in) return false;
            for_each_octant_group(signbits(f[3]), signbits(f[4]), signbits(f[5]), in,
                                  [&](uint32_t lanes, uint32_t octant) {
                                      s.parts[octant].push_back(Part{x0, y0, lanes});
                                  });
        }
    if (tree.nodes.empty()) {
        for (Hit& h : hits) h = Hit{};
        return true;
    }

    const Bbox3f box = padded_bounds(tree.bounds);
    for (uint32_t o = 0; o < 8; ++o) {
        const std::vector<Part>& parts = s.parts[o];
        const int n = int(parts.size());
        if (n == 0) continue;
        s.blocks.resize(size_t(n));
        s.bounds.reset(n);
        for (int i = 0; i < n; ++i) {
            vf f[8];
            load_square(rays, width, height, parts[size_t(i)].x0, parts[size_t(i)].y0, f);
            init_block(s.blocks[size_t(i)], s.bounds, i, f, parts[size_t(i)].lanes,
                       parts[size_t(i)].y0 * width + parts[size_t(i)].x0, box);
        }
        traverse_group(tree, triangles, org, o, s.blocks.data(), s.bounds, n);
        for (const Block& b : s.blocks) {
            if (b.in == all_lanes<K>) {
                // Whole squares: the hits as (t, triangle) pairs, one row of the square at a time.
                alignas(64) float pairs[2 * K];
                storeu_pairs(pairs, b.best.t, as_float(b.best.tri));
                for (int r = 0; r < ph; ++r)
                    std::memcpy(static_cast<void*>(&hits[size_t(b.sample + r * width)]),
                                pairs + 2 * pw * r, sizeof(Hit) * pw);
                continue;
            }
            for (uint32_t l = b.in; l; l &= l - 1) {
                const int lane = std::countr_zero(l);
                hits[size_t(b.sample + (lane / pw) * width + lane % pw)] =
                    Hit{b.best.t[lane], uint32_t(b.best.tri[lane])};
            }
        }
    }
    return true;
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
