// Binned SAH over triangle centroids (up to 16 bins per axis, fewer in small nodes), W children
// per node: near the root by opening the largest child until W are there, below by collapsing
// the binary tree at the least SAH cost (WideBuilder); with a budget, spatial splits too (SBVH:
// Stich, Friedrich and Dietrich 2009), whose copies of a triangle are clipped to each side
// conservatively. Large nodes bin in parallel and the subtrees under them are built in parallel on
// disjoint ranges of references, then laid out in a fixed order, so the tree is the same for any
// number of threads.
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <memory>
#include <vector>

#include "bvh/bvh.h"
#include "kdtree/kd_clip.h"
#include "rtt/error.h"
#include "simd/simd.h"
#include "trace/trace_ray.h"

namespace rtt {
namespace {

constexpr int max_bins = 16;
/// Bins for a node of n references: fewer for small nodes, where sweeping 16 empty bins
/// cost more than the binning (min(16, 4 + n / 20), as Embree's builders bin).
int bins_for(uint32_t n) {
    return int(std::min<uint32_t>(max_bins, 4 + n / 20));
}
// A block of four triangles costs about two node tests (docs/benchmarks.md, "Arbitrary rays").
constexpr float traversal_cost = 1.f, intersection_cost = 2.f;
constexpr int sah_depth = 64;
/// Ranges of at most one block are leaves without a decision: splitting them rarely paid, and
/// deciding them was an eighth of the build (docs/benchmarks.md, "Arbitrary rays"; two blocks
/// cost random rays 4-7 %).
constexpr uint32_t always_leaf = 4;
/// The overlap of an object split's children, as a part of the scene's surface, beyond which
/// spatial splits are tried: Stich et al. take 1e-5; 3e-3 gives nearly the same SAH cost in
/// under half the build time (docs/benchmarks.md, "Arbitrary rays").
constexpr float spatial_overlap = 3e-3f;
/// Below this many references a node's work stays on one thread.
constexpr uint32_t parallel_refs = 16384;

/// A box as two vectors (x, y, z, -): what every pass of the build extends and compares.
struct Box4 {
    vfloat4 lo{pos_inf}, hi{neg_inf};
    RTT_FORCEINLINE void extend(vfloat4 l, vfloat4 h) {
        lo = min(lo, l);
        hi = max(hi, h);
    }
    void extend(const Box4& b) { extend(b.lo, b.hi); }
    bool empty() const { return !(lo[0] <= hi[0]); }
    float half_area() const {
        const vfloat4 d = hi - lo;
        return d[0] * d[1] + d[0] * d[2] + d[1] * d[2];
    }
    Bbox3f box() const {
        Bbox3f b;
        b.lo = {lo[0], lo[1], lo[2]};
        b.hi = {hi[0], hi[1], hi[2]};
        return b;
    }
};

/// A triangle's bounds, partitioned in place as the tree is built (sequential passes, no
/// gather through an index). Lane 3 of lo holds the triangle's index, of hi its area (a copy
/// made by a spatial split keeps the whole triangle's).
struct alignas(32) PrimRef {
    alignas(16) float lo[4];
    alignas(16) float hi[4];
    uint32_t id() const { return std::bit_cast<uint32_t>(lo[3]); }
    Bbox3f box() const { return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}}; }
    void set_box(const Bbox3f& b) {
        for (int a = 0; a < 3; ++a) {
            lo[a] = b.lo[a];
            hi[a] = b.hi[a];
        }
    }
    /// lo + hi, twice the centroid (the index masked out of lane 3).
    RTT_FORCEINLINE vfloat4 centroid2() const {
        const vint4 xyz(_mm_setr_epi32(-1, -1, -1, 0));
        return as_float(as_int(vfloat4::load(lo) + vfloat4::load(hi)) & xyz);
    }
    float area() const { return hi[3]; }
};

/// The bounds of a node's references and of their (doubled) centroids, and their triangles'
/// areas summed (in the order added: only serial passes sum what orders a node's children).
struct Extent {
    Box4 box, centroids;
    float area = 0.f;
    RTT_FORCEINLINE void add(const PrimRef& r) {
        box.extend(vfloat4::load(r.lo), vfloat4::load(r.hi));
        const vfloat4 c = r.centroid2();
        centroids.extend(c, c);
        area += r.area();
    }
    void merge(const Extent& o) {
        box.extend(o.box);
        centroids.extend(o.centroids);
        area += o.area;
    }
};

/// Where doubled centroids fall among `n` equal bins per axis of a node's centroid bounds.
/// NaN (0 * inf from a zero or denormal extent, inf - inf from huge coordinates) goes to bin 0,
/// the same when binning and when partitioning.
struct BinMap {
    int n;
    vfloat4 lo, scale, last;
    BinMap(const Box4& centroids, int n_)
        : n(n_),
          lo(centroids.lo),
          scale(vfloat4(float(n_)) / (centroids.hi - centroids.lo)),
          last(float(n_ - 1)) {}
    RTT_FORCEINLINE vint4 operator()(vfloat4 c) const {
        // maxps returns its second operand for NaN: max(NaN, 0) = 0.
        return truncate_to_int(min(max((c - lo) * scale, vfloat4(0.f)), last));
    }
};

/// Per axis, the bounds and counts of the references whose centroid falls in each of the
/// first n bins (only those are set: a small node's bins are cleared for each node).
struct Bins {
    int n;
    std::array<std::array<Box4, max_bins>, 3> box;
    std::array<std::array<uint32_t, max_bins>, 3> count;

    explicit Bins(int n_ = max_bins) : n(n_) {
        for (size_t a = 0; a < 3; ++a)
            for (size_t b = 0; b < size_t(n); ++b) {
                box[a][b] = Box4{};
                count[a][b] = 0;
            }
    }
    void merge(const Bins& o) {
        for (size_t a = 0; a < 3; ++a)
            for (size_t b = 0; b < size_t(n); ++b) {
                box[a][b].extend(o.box[a][b]);
                count[a][b] += o.count[a][b];
            }
    }
};

/// f(lo, hi) over [first, end) on one thread, or in parallel with `merge` when large. Every
/// reduction used here is exact (min, max, integer sums), so the result is the serial one.
template <typename T, typename F, typename M>
T reduce_range(uint32_t first, uint32_t end, F&& f, M&& merge) {
    if (end - first < parallel_refs) return f(first, end);
    return tbb::parallel_reduce(
        tbb::blocked_range<uint32_t>(first, end, parallel_refs / 4), T{},
        [&](const tbb::blocked_range<uint32_t>& r, T acc) {
            merge(acc, f(r.begin(), r.end()));
            return acc;
        },
        [&](T a, const T& b) {
            merge(a, b);
            return a;
        });
}

/// A node's references [first, end), room for the copies spatial splits make up to `cap`, and
/// their extent, with its split decided when it is made: a leaf; the plane `pos` along
/// `spatial_axis` (a spatial split); the centroid boundary below bin `bin` along `axis`; or (no
/// axis, not a leaf) halves.
struct Range {
    uint32_t first = 0, end = 0, cap = 0;
    int depth = 0;
    Extent ext;
    bool leaf = false;
    int axis = -1, bin = 0;
    int spatial_axis = -1;
    float pos = 0.f;
    uint32_t size() const { return end - first; }
};

/// Per axis, the clipped bounds of the references' parts in each of n slabs of a node's box,
/// and how many references start (`enter`) and end (`exit`) in each (Stich, Friedrich and
/// Dietrich 2009).
struct SpatialBins {
    int n;
    std::array<std::array<Box4, max_bins>, 3> box;
    std::array<std::array<uint32_t, max_bins>, 3> enter, exit;

    explicit SpatialBins(int n_ = max_bins) : n(n_) {
        for (size_t a = 0; a < 3; ++a)
            for (size_t b = 0; b < size_t(n); ++b) {
                box[a][b] = Box4{};
                enter[a][b] = exit[a][b] = 0;
            }
    }
    void merge(const SpatialBins& o) {
        for (size_t a = 0; a < 3; ++a)
            for (size_t b = 0; b < size_t(n); ++b) {
                box[a][b].extend(o.box[a][b]);
                enter[a][b] += o.enter[a][b];
                exit[a][b] += o.exit[a][b];
            }
    }
};

/// The n - 1 planes between n equal slabs of a box along each axis, and which slab a
/// reference's faces fall in, decided by comparing with the planes themselves so that the
/// counts agree with the split (a part at a plane belongs to the slab above it).
struct SlabPlanes {
    int n;
    std::array<std::array<float, max_bins + 1>, 3> at;  ///< at[a][b]: the lower face of slab b.

    SlabPlanes(const Box4& box, int n_) : n(n_) {
        for (size_t a = 0; a < 3; ++a) {
            const float lo = box.lo[int(a)], d = box.hi[int(a)] - lo;
            at[a][0] = neg_inf;
            for (int b = 1; b < n; ++b) at[a][size_t(b)] = lo + d * (float(b) / float(n));
            at[a][size_t(n)] = pos_inf;
        }
    }
    /// The slab holding x: the last whose lower face is <= x.
    int slab(int a, float x) const {
        const auto& p = at[size_t(a)];
        return int(std::upper_bound(p.begin() + 1, p.begin() + n, x) - p.begin()) - 1;
    }
    /// The slab holding a part's upper face hi (> its lower faces strictly), not below `from`.
    int last_slab(int a, float hi, int from) const {
        const auto& p = at[size_t(a)];
        return std::max(from,
                        int(std::lower_bound(p.begin() + 1, p.begin() + n, hi) - p.begin()) - 1);
    }
};

/// Builds the W-wide tree: a node's range is split in two by binned SAH, each range split once.
/// Nodes over at least parallel_refs references are planned first, each by splitting the child
/// with the largest surface that is not a leaf again until W children are there, sibling
/// subtrees in parallel (plan), then laid out depth first (place). The subtrees under them are
/// built as tasks, each its binary tree collapsed into wide nodes (make_node), in parallel, and
/// placed after them in the order the tasks were found, so the layout does not depend on the
/// thread count.
template <int W>
class WideBuilder {
public:
    WideBuilder(const BuildTriangles& tris, const BvhBuildOptions& options)
        : tris_(tris),
          refs_(tris.size() + size_t(double(tris.size()) * double(options.spatial_split_budget))) {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, tris.size(), 4096),
                          [&](const tbb::blocked_range<size_t>& r) {
                              for (size_t i = r.begin(); i < r.end(); ++i) {
                                  const TriangleVerts t = tris[i];
                                  PrimRef& p = refs_[i];
                                  for (int a = 0; a < 3; ++a) {
                                      p.lo[a] = std::min(std::min(t.v0[a], t.v1[a]), t.v2[a]);
                                      p.hi[a] = std::max(std::max(t.v0[a], t.v1[a]), t.v2[a]);
                                  }
                                  p.lo[3] = std::bit_cast<float>(uint32_t(i));
                                  const Vec3f n = cross(t.v1 - t.v0, t.v2 - t.v0);
                                  p.hi[3] = 0.5f * std::sqrt(dot(n, n));
                              }
                          });
    }

    Bvh<W> build() {
        Bvh<W> out;
        Range root{0, uint32_t(tris_.size()), uint32_t(refs_.size())};
        root.ext = reduce_range<Extent>(
            0, root.end,
            [&](uint32_t lo, uint32_t hi) {
                Extent e;
                for (uint32_t i = lo; i < hi; ++i) e.add(refs_[i]);
                return e;
            },
            [](Extent& a, const Extent& b) { a.merge(b); });
        root_area_ = root.ext.box.half_area();
        decide(root);
        out.padded_bounds = padded_bounds(root.ext.box.box());
        out.blocks.reserve(refs_.size() / 2);
        out.nodes.emplace_back();
        if (root.leaf) {  // the whole scene is one leaf: a root with one leaf child
            write_node(&root, 1, 0, out, [](int) { return true; });
            return out;
        }
        std::vector<Task> tasks;
        place(*plan(root), 0, out, tasks);
        build_tasks(tasks, out);
        return out;
    }

private:
    /// A subtree left for later: its range, and the child slot of its parent node.
    struct Task {
        Range range;
        uint32_t parent;
        int slot;
    };

    /// Decides r's split: binned SAH over its centroids (16 bins, fewer in small nodes).
    void decide(Range& r) const {
        const uint32_t n = r.size();
        if (n <= always_leaf) {
            r.leaf = true;
            return;
        }
        const Extent& ext = r.ext;
        float best_cost = intersection_cost * blocks_of(n);
        const BinMap map(ext.centroids, bins_for(n));
        // Past sah_depth only halves: the tree (and the traversal's stack) stays shallow
        // whatever the input (bvh_max_depth).
        if (r.depth < sah_depth) {
            const Bins all = bin_all(r.first, r.end, map);
            const float parent = ext.box.half_area();
            Box4 best_left, best_right;
            for (int a = 0; a < 3; ++a) {
                if (!(ext.centroids.hi[a] - ext.centroids.lo[a] > 0.f)) continue;
                sweep(all.box[size_t(a)], all.count[size_t(a)], all.count[size_t(a)], map.n, parent,
                      n, best_cost, [&](int b, const Box4& lb, const Box4& rb) {
                          r.axis = a;
                          r.bin = b;
                          best_left = lb;
                          best_right = rb;
                      });
            }
            // Spatial splits where the best object split's children overlap by more than a
            // part of the scene's surface (Stich et al.) and copies still fit.
            if (r.cap > r.end &&
                (r.axis < 0 || overlap(best_left, best_right) > spatial_overlap * root_area_))
                decide_spatial(r, parent, best_cost);
        }
        // No useful split (centroids coincide) or too deep: a leaf if it may be one, else halves.
        r.leaf = r.axis < 0 && r.spatial_axis < 0 && n <= bvh_leaf_max;
    }

    /// The SAH sweep over n bins of one axis: the left side of boundary b holds the bins below
    /// it (entering there: `left_count`), the right the bins from b on (`right_count`). Calls
    /// better(b, left box, right box) for each boundary cheaper than best_cost, which it lowers,
    /// among those whose sides hold at most max_refs references together.
    template <typename Better>
    static void sweep(const std::array<Box4, max_bins>& box,
                      const std::array<uint32_t, max_bins>& left_count,
                      const std::array<uint32_t, max_bins>& right_count, int n, float parent,
                      uint32_t max_refs, float& best_cost, Better&& better) {
        std::array<Box4, max_bins> right_box;
        std::array<uint32_t, max_bins> right_sum{};
        Box4 rb;
        uint32_t rc = 0;
        for (int b = n - 1; b > 0; --b) {
            rb.extend(box[size_t(b)]);
            rc += right_count[size_t(b)];
            right_box[size_t(b)] = rb;
            right_sum[size_t(b)] = rc;
        }
        Box4 lb;
        uint32_t lc = 0;
        for (int b = 1; b < n; ++b) {
            lb.extend(box[size_t(b - 1)]);
            lc += left_count[size_t(b - 1)];
            const uint32_t rcount = right_sum[size_t(b)];
            if (lc == 0 || rcount == 0 || lc + rcount > max_refs) continue;
            const float cost =
                traversal_cost + intersection_cost *
                                     (lb.half_area() * blocks_of(lc) +
                                      right_box[size_t(b)].half_area() * blocks_of(rcount)) /
                                     parent;
            if (cost < best_cost) {
                best_cost = cost;
                better(b, lb, right_box[size_t(b)]);
            }
        }
    }

    static float overlap(const Box4& a, const Box4& b) {
        Box4 both;
        both.lo = max(a.lo, b.lo);
        both.hi = min(a.hi, b.hi);
        const vfloat4 d = both.hi - both.lo;
        if (!(d[0] >= 0.f && d[1] >= 0.f && d[2] >= 0.f)) return 0.f;
        return both.half_area();
    }

    /// Spatial splits of r: every slab plane of its box, the references' parts clipped to the
    /// slabs; takes the cheapest if it beats best_cost.
    void decide_spatial(Range& r, float parent, float& best_cost) const {
        const int n = bins_for(r.size());
        const SlabPlanes planes(r.ext.box, n);
        const SpatialBins all = bin_spatial(r.first, r.end, planes);
        for (int a = 0; a < 3; ++a) {
            if (!(r.ext.box.hi[a] - r.ext.box.lo[a] > 0.f)) continue;
            sweep(all.box[size_t(a)], all.enter[size_t(a)], all.exit[size_t(a)], n, parent,
                  r.cap - r.first, best_cost, [&](int b, const Box4&, const Box4&) {
                      r.spatial_axis = a;
                      r.pos = planes.at[size_t(a)][size_t(b)];
                  });
        }
    }

    /// Splits the inner range r as decided into `left` and `right`, and decides theirs.
    void open(const Range& r, Range& left, Range& right) {
        const uint32_t first = r.first, n = r.size();
        uint32_t end = r.end, mid;
        left = Range{};
        right = Range{};
        if (r.spatial_axis >= 0) {
            const int a = r.spatial_axis;
            const float pos = r.pos;
            end = split_straddlers(r);
            mid = partition(
                first, end, [&](const PrimRef& p) { return p.lo[a] < pos; }, left.ext, right.ext);
        } else if (r.axis >= 0) {
            const BinMap map(r.ext.centroids, bins_for(n));
            const int a = r.axis, bin = r.bin;
            mid = partition(
                first, end, [&](const PrimRef& p) { return map(p.centroid2())[a] < bin; }, left.ext,
                right.ext);
        } else {  // halves by centroid order
            const vfloat4 d = r.ext.centroids.hi - r.ext.centroids.lo;
            const int a = d[0] >= d[1] ? (d[0] >= d[2] ? 0 : 2) : (d[1] >= d[2] ? 1 : 2);
            mid = first + n / 2;
            std::nth_element(refs_.begin() + first, refs_.begin() + mid, refs_.begin() + end,
                             [&](const PrimRef& x, const PrimRef& y) {
                                 const float cx = x.centroid2()[a], cy = y.centroid2()[a];
                                 return cx < cy || (cx == cy && x.id() < y.id());
                             });
            for (uint32_t i = first; i < mid; ++i) left.ext.add(refs_[i]);
            for (uint32_t i = mid; i < end; ++i) right.ext.add(refs_[i]);
        }
        // The room left for copies, shared in proportion to the references: the right side's
        // moved up to make the left side's.
        const uint32_t room = r.cap - end;
        const uint32_t left_room = uint32_t(uint64_t(room) * (mid - first) / (end - first));
        if (left_room > 0) std::move_backward(&refs_[mid], &refs_[end], &refs_[end + left_room]);
        left.first = first;
        left.end = mid;
        left.cap = mid + left_room;
        right.first = mid + left_room;
        right.end = end + left_room;
        right.cap = r.cap;
        left.depth = right.depth = r.depth + 1;
        if (n >= parallel_refs)
            tbb::parallel_invoke([&] { decide(left); }, [&] { decide(right); });
        else {
            decide(left);
            decide(right);
        }
    }

    /// The children of the inner range r: its two halves, then the largest inner child opened
    /// until there are W. Returns how many.
    int children(const Range& r, Range* kids) {
        open(r, kids[0], kids[1]);
        int n = 2;
        while (n < W) {
            int pick = -1;
            float area = -1.f;
            for (int i = 0; i < n; ++i) {
                const float a = kids[i].ext.box.half_area();
                if (!kids[i].leaf && a > area) {
                    area = a;
                    pick = i;
                }
            }
            if (pick < 0) break;
            const Range opened = kids[pick];
            open(opened, kids[pick], kids[n++]);
        }
        order_for_any_hit(kids, n);
        return n;
    }

    /// Orders a node's children as any-hit rays take them (slot order): by the chance that a
    /// ray entering the child meets one of its triangles (their areas over half the box's
    /// surface, Cauchy's formula for random lines, summed) per triangle it must test, highest
    /// first: a cheap likely blocker before a costly unlikely one (Ize and Hansen 2011 order
    /// occlusion rays by such a ratio). Closest-hit rays sort the children by distance anyway;
    /// docs/benchmarks.md, "Arbitrary rays", has the measurement. `tags`, if given, go with
    /// their kids.
    static void order_for_any_hit(Range* kids, int n, int* tags = nullptr) {
        double key[W];
        int order[W];
        for (int i = 0; i < n; ++i) {
            const double cost = double(kids[i].ext.box.half_area()) * double(kids[i].size());
            const double k = cost > 0.0 ? double(kids[i].ext.area) / cost : 0.0;
            key[i] = k == k ? k : 0.0;  // 0 for NaN (inf / inf)
            order[i] = i;
        }
        std::stable_sort(order, order + n, [&](int a, int b) { return key[a] > key[b]; });
        Range sorted[W];
        int sorted_tags[W];
        for (int i = 0; i < n; ++i) {
            sorted[i] = kids[order[i]];
            if (tags) sorted_tags[i] = tags[order[i]];
        }
        std::copy(sorted, sorted + n, kids);
        if (tags) std::copy(sorted_tags, sorted_tags + n, tags);
    }

    /// The children of a node of at least parallel_refs references (or the root), and the
    /// plans of those children that are that large too: made in parallel, laid out afterwards.
    struct TopNode {
        Range kids[W];
        int n = 0;
        std::unique_ptr<TopNode> below[W];
    };

    /// Splits the inner range r and, in parallel, its large inner children (disjoint ranges).
    std::unique_ptr<TopNode> plan(const Range& r) {
        auto top = std::make_unique<TopNode>();
        top->n = children(r, top->kids);
        tbb::parallel_for(0, top->n, [&](int i) {
            const Range& k = top->kids[i];
            if (!k.leaf && k.size() >= parallel_refs) top->below[i] = plan(k);
        });
        return top;
    }

    /// The node with children kids[0, n) at out.nodes[index]: leaf children appended, the inner
    /// children that `now` accepts given the next slots (the others left for the caller).
    /// Returns which children got slots.
    template <typename Now>
    uint32_t write_node(const Range* kids, int n, uint32_t index, Bvh<W>& out, Now&& now) {
        BvhNode<W> node{};
        node.count = uint32_t(n);
        uint32_t slotted = 0;
        for (int i = 0; i < W; ++i)
            for (int a = 0; a < 3; ++a) {
                node.lo[a][i] = i < n ? kids[i].ext.box.lo[a] : pos_inf;
                node.hi[a][i] = i < n ? kids[i].ext.box.hi[a] : neg_inf;
            }
        for (int i = 0; i < n; ++i) {
            if (kids[i].leaf) {
                node.child[i] = leaf_child(kids[i], out);
            } else if (now(i)) {
                node.child[i] = uint32_t(out.nodes.size());
                out.nodes.emplace_back();
                slotted |= 1u << i;
            }
        }
        out.nodes[index] = node;
        return slotted;
    }

    /// Lays out the planned nodes under `top` from out.nodes[index] on, depth first; the
    /// subtrees below them become `tasks` (their slots patched when built).
    void place(const TopNode& top, uint32_t index, Bvh<W>& out, std::vector<Task>& tasks) {
        const uint32_t slotted =
            write_node(top.kids, top.n, index, out, [&](int i) { return bool(top.below[i]); });
        for (int i = 0; i < top.n; ++i) {
            if ((slotted >> i) & 1u)
                place(*top.below[i], out.nodes[index].child[i], out, tasks);
            else if (!top.kids[i].leaf)
                tasks.push_back({top.kids[i], index, i});
        }
    }

    /// A range of the binary tree a subtree is collapsed from (a leaf or a node, as the binary
    /// tree has it), and its subtree's least SAH cost as up to i roots side by side
    /// (cost[i - 1]) and how that is reached.
    struct BinaryNode {
        Range range;
        int left = -1, right = -1;  ///< -1: not split (a leaf)
        float cost[W];
        /// For i >= 2 roots: the roots the left side takes (split[i - 1]), 0 for i - 1 roots.
        uint8_t split[W];
        uint8_t node_split = 1;  ///< The left side's roots among the W children of a node here.
        /// The most roots the subtree can stand as: its leaves, at most W (cost and split past
        /// it repeat the last).
        uint8_t most = 1;
    };

    /// Writes the subtree over the inner range r from out.nodes[index] on, depth first: its
    /// binary SAH tree is built whole, then collapsed into W-wide nodes at the least SAH cost
    /// (Ylitie, Karras and Laine 2017). Opening the largest child instead, as the nodes above
    /// do, left most of the lowest nodes with two or three leaves (docs/benchmarks.md,
    /// "Arbitrary rays").
    void make_node(const Range& r, uint32_t index, Bvh<W>& out) {
        // Each thread's binary tree reuses its memory from task to task (fresh pages cost
        // about a millisecond per MB on these VMs).
        std::vector<BinaryNode>& tree = binary_trees_.local();
        tree.clear();
        grow(r, tree);
        write_collapsed(tree, 0, index, out);
    }

    /// Appends the binary tree over r to `tree` (r first) with every cost; returns r's index.
    int grow(const Range& r, std::vector<BinaryNode>& tree) {
        const int at = int(tree.size());
        tree.push_back({r});
        if (!r.leaf) {
            Range left, right;
            open(r, left, right);
            const int l = grow(left, tree);
            const int h = grow(right, tree);
            tree[size_t(at)].left = l;
            tree[size_t(at)].right = h;
        }
        BinaryNode& b = tree[size_t(at)];
        const float area = r.ext.box.half_area();
        if (b.left < 0) {
            std::fill(b.cost, b.cost + W, area * intersection_cost * blocks_of(r.size()));
            std::fill(b.split, b.split + W, uint8_t(0));
            return at;
        }
        const BinaryNode &l = tree[size_t(b.left)], &h = tree[size_t(b.right)];
        const int most = std::min(W, l.most + h.most);
        b.most = uint8_t(most);
        // The cheapest way to put i <= most roots side by side: k from the left side, i - k from
        // the right, each side at most its own most (beyond, its costs repeat).
        const auto spread = [&](int i, int& best_k) {
            float best = pos_inf;
            best_k = std::max(1, i - h.most);
            for (int k = best_k; k <= std::min(i - 1, int(l.most)); ++k) {
                const float c = l.cost[k - 1] + h.cost[i - k - 1];
                if (c < best) {
                    best = c;
                    best_k = k;
                }
            }
            return best;
        };
        // A range the binary tree splits is a node: as a leaf it would no longer hold its
        // references where copies were made below it (they moved). The binary SAH found the
        // split cheaper than a leaf, and the node costs no more than the split.
        int k = 1;
        b.cost[0] = area * traversal_cost + spread(most, k);
        b.node_split = uint8_t(k);
        b.split[0] = 0;
        for (int i = 2; i <= W; ++i) {
            const float c = i <= most ? spread(i, k) : pos_inf;
            const bool more = c < b.cost[i - 2];
            b.cost[i - 1] = more ? c : b.cost[i - 2];
            b.split[i - 1] = more ? uint8_t(k) : uint8_t(0);
        }
        return at;
    }

    /// Appends to ids[n...] the roots of tree[at] as up to i side by side.
    static void roots(const std::vector<BinaryNode>& tree, int at, int i, int* ids, int& n) {
        const BinaryNode& b = tree[size_t(at)];
        while (i > 1 && b.split[i - 1] == 0) --i;
        if (i == 1) {
            ids[n++] = at;
            return;
        }
        const int k = b.split[i - 1];
        roots(tree, b.left, k, ids, n);
        roots(tree, b.right, i - k, ids, n);
    }

    /// Writes tree[at] as a node at out.nodes[index], and the nodes under it depth first.
    void write_collapsed(const std::vector<BinaryNode>& tree, int at, uint32_t index, Bvh<W>& out) {
        const BinaryNode& b = tree[size_t(at)];
        int ids[W], n = 0;
        roots(tree, b.left, b.node_split, ids, n);
        roots(tree, b.right, W - b.node_split, ids, n);
        Range kids[W];
        for (int i = 0; i < n; ++i) kids[i] = tree[size_t(ids[i])].range;
        order_for_any_hit(kids, n, ids);
        const uint32_t slotted = write_node(kids, n, index, out, [](int) { return true; });
        for (int i = 0; i < n; ++i)
            if ((slotted >> i) & 1u) write_collapsed(tree, ids[i], out.nodes[index].child[i], out);
    }

    /// Builds the tasks' subtrees after out's nodes and blocks, in task order: in parallel into
    /// arrays of their own, then moved into place, or on one thread straight into out.
    void build_tasks(const std::vector<Task>& tasks, Bvh<W>& out) {
        const auto subtree = [&](const Task& t, Bvh<W>& into) {
            const uint32_t root = uint32_t(into.nodes.size());
            into.nodes.emplace_back();
            make_node(t.range, root, into);
            return root;
        };
        if (tbb::this_task_arena::max_concurrency() == 1 || tasks.size() < 2) {
            for (const Task& t : tasks) {
                const uint32_t root = subtree(t, out);
                out.nodes[t.parent].child[t.slot] = root;
            }
            return;
        }
        std::vector<Bvh<W>> parts(tasks.size());
        tbb::parallel_for(size_t(0), tasks.size(), [&](size_t i) { subtree(tasks[i], parts[i]); });
        std::vector<uint32_t> node_at(tasks.size() + 1), block_at(tasks.size() + 1);
        node_at[0] = uint32_t(out.nodes.size());
        block_at[0] = uint32_t(out.blocks.size());
        for (size_t i = 0; i < tasks.size(); ++i) {
            node_at[i + 1] = node_at[i] + uint32_t(parts[i].nodes.size());
            block_at[i + 1] = block_at[i] + uint32_t(parts[i].blocks.size());
        }
        out.nodes.resize(node_at.back());
        out.blocks.resize(block_at.back());
        tbb::parallel_for(size_t(0), tasks.size(), [&](size_t i) {
            const Bvh<W>& p = parts[i];
            std::copy(p.blocks.begin(), p.blocks.end(), out.blocks.begin() + block_at[i]);
            for (size_t k = 0; k < p.nodes.size(); ++k) {
                BvhNode<W> node = p.nodes[k];
                for (uint32_t c = 0; c < node.count; ++c)
                    node.child[c] += node.child[c] & bvh_leaf_bit ? block_at[i] << 3 : node_at[i];
                out.nodes[node_at[i] + k] = node;
            }
            out.nodes[tasks[i].parent].child[tasks[i].slot] = node_at[i];
        });
    }

    Bins bin_all(uint32_t first, uint32_t end, const BinMap& map) const {
        return reduce_range<Bins>(
            first, end,
            [&](uint32_t from, uint32_t to) {
                Bins out(map.n);
                alignas(16) int32_t b[4];
                for (uint32_t i = from; i < to; ++i) {
                    const PrimRef& r = refs_[i];
                    store(b, map(r.centroid2()));
                    const vfloat4 lo = vfloat4::load(r.lo), hi = vfloat4::load(r.hi);
                    for (size_t a = 0; a < 3; ++a) {
                        out.box[a][size_t(b[a])].extend(lo, hi);
                        ++out.count[a][size_t(b[a])];
                    }
                }
                return out;
            },
            [](Bins& x, const Bins& y) { x.merge(y); });
    }

    /// Moves the references of [first, end) that go left to the front; returns where the rest
    /// start, with both sides' extents.
    template <typename GoesLeft>
    uint32_t partition(uint32_t first, uint32_t end, GoesLeft&& goes_left, Extent& left,
                       Extent& right) {
        // Local extents stay in registers (the references' swaps could alias the callers').
        Extent l = left, r = right;
        uint32_t i = first, j = end;
        for (;;) {
            while (i < j && goes_left(refs_[i])) l.add(refs_[i++]);
            while (i < j && !goes_left(refs_[j - 1])) r.add(refs_[--j]);
            if (i >= j) break;
            std::swap(refs_[i], refs_[j - 1]);
        }
        left = l;
        right = r;
        return i;
    }

    /// Each reference of r that crosses its spatial plane clipped to both sides: the part
    /// below stays in place, the part above is appended after r's end. A part only on the
    /// plane is dropped: the closed part on the other side holds its points. Returns the new
    /// end (at most r.cap: the split's bins counted every crossing).
    uint32_t split_straddlers(const Range& r) {
        const int a = r.spatial_axis;
        const float pos = r.pos;
        uint32_t end = r.end;
        for (uint32_t i = r.first; i < r.end; ++i) {
            PrimRef& p = refs_[i];
            if (!(p.lo[a] < pos && pos < p.hi[a])) continue;
            const ClippedSides sides = clip_triangle_to_children(tris_[p.id()], p.box(), a, pos);
            const bool left = sides.left && sides.left_box.lo[a] < pos;
            const bool right = sides.right && sides.right_box.hi[a] > pos;
            if (left && right) {
                PrimRef& copy = refs_[end++];
                copy = p;
                copy.set_box(sides.right_box);
                p.set_box(sides.left_box);
            } else if (left || right) {
                p.set_box(left ? sides.left_box : sides.right_box);
            }
        }
        return end;
    }

    SpatialBins bin_spatial(uint32_t first, uint32_t end, const SlabPlanes& planes) const {
        return reduce_range<SpatialBins>(
            first, end,
            [&](uint32_t from, uint32_t to) {
                SpatialBins out(planes.n);
                for (uint32_t i = from; i < to; ++i) {
                    const PrimRef& p = refs_[i];
                    const vfloat4 lo = vfloat4::load(p.lo), hi = vfloat4::load(p.hi);
                    for (int a = 0; a < 3; ++a) {
                        const int b0 = planes.slab(a, p.lo[a]);
                        const int b1 = planes.last_slab(a, p.hi[a], b0);
                        ++out.enter[size_t(a)][size_t(b0)];
                        ++out.exit[size_t(a)][size_t(b1)];
                        if (b0 == b1) {
                            out.box[size_t(a)][size_t(b0)].extend(lo, hi);
                            continue;
                        }
                        // The part in each slab, the rest split again at the next plane.
                        const TriangleVerts tri = tris_[p.id()];
                        Box4 rest{lo, hi};
                        for (int b = b0; b < b1; ++b) {
                            Box4 below;
                            split_estimate(tri, a, planes.at[size_t(a)][size_t(b + 1)], rest,
                                           below);
                            out.box[size_t(a)][size_t(b)].extend(below);
                        }
                        out.box[size_t(a)][size_t(b1)].extend(rest);
                    }
                }
                return out;
            },
            [](SpatialBins& x, const SpatialBins& y) { x.merge(y); });
    }

    /// The parts of `box` ∩ tri below and above the plane at `pos` along axis a, in float
    /// (Embree's splitter): `box` becomes the part above. Only the binning's estimate of the
    /// children's surfaces: split_straddlers clips conservatively.
    static void split_estimate(const TriangleVerts& tri, int a, float pos, Box4& box, Box4& below) {
        Box4 above;
        const Vec3f* v[3] = {&tri.v0, &tri.v1, &tri.v2};
        for (int i = 0; i < 3; ++i) {
            const Vec3f &p = *v[i], &q = *v[(i + 1) % 3];
            const vfloat4 pv = vfloat4::setr(p.x, p.y, p.z, 0.f);
            if (p[a] <= pos) below.extend(pv, pv);
            if (p[a] >= pos) above.extend(pv, pv);
            if ((p[a] < pos && pos < q[a]) || (q[a] < pos && pos < p[a])) {
                const float t = (pos - p[a]) / (q[a] - p[a]);
                const vfloat4 qv = vfloat4::setr(q.x, q.y, q.z, 0.f);
                const vfloat4 c = pv + vfloat4(t) * (qv - pv);
                below.extend(c, c);
                above.extend(c, c);
            }
        }
        below.lo = max(below.lo, box.lo);
        below.hi = min(below.hi, box.hi);
        box.lo = max(above.lo, box.lo);
        box.hi = min(above.hi, box.hi);
    }

    /// The leaf child of range r: its triangles appended to out's blocks, four to a block.
    uint32_t leaf_child(const Range& r, Bvh<W>& out) const {
        const uint32_t block = uint32_t(out.blocks.size()), count = r.size();
        const uint32_t blocks = (count + 3) / 4;
        for (uint32_t b = 0; b < blocks; ++b) {
            BvhTriangles4 q{};
            for (uint32_t l = 0; l < 4; ++l) {
                const uint32_t k = b * 4 + l;
                const uint32_t id = k < count ? refs_[r.first + k].id() : invalid_triangle;
                const TriangleVerts t = tris_[k < count ? id : refs_[r.first].id()];
                for (int a = 0; a < 3; ++a) {
                    q.v0[a][l] = t.v0[a];
                    q.v1[a][l] = t.v1[a];
                    q.v2[a][l] = t.v2[a];
                }
                q.id[l] = id;
            }
            out.blocks.push_back(q);
        }
        return bvh_leaf_bit | (block << 3) | blocks;
    }

    // Leaves test four triangles at once: the SAH counts blocks of four.
    static float blocks_of(uint32_t n) { return float((n + 3) / 4); }

    BuildTriangles tris_;         ///< Spans: the caller keeps the triangles alive.
    large_vector<PrimRef> refs_;  ///< The triangles' references, then room for copies.
    tbb::enumerable_thread_specific<std::vector<BinaryNode>> binary_trees_;
    float root_area_ = 0.f;
};

}  // namespace

template <int W>
Bvh<W> build_bvh(const BuildTriangles& triangles, const BvhBuildOptions& options) {
    if (triangles.size() >= bvh_max_triangles)
        throw Error("the bvh tracer takes at most 134,217,727 triangles");
    // At most 2^28 references: every leaf block stays addressable.
    if (!(options.spatial_split_budget >= 0.f && options.spatial_split_budget <= 1.f))
        throw Error("the bvh's spatial split budget must lie in [0, 1]");
    if (triangles.empty()) return {};
    return WideBuilder<W>(triangles, options).build();
}

template Bvh<4> build_bvh<4>(const BuildTriangles&, const BvhBuildOptions&);
template Bvh<8> build_bvh<8>(const BuildTriangles&, const BvhBuildOptions&);
template Bvh<16> build_bvh<16>(const BuildTriangles&, const BvhBuildOptions&);

}  // namespace rtt
