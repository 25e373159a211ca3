// Binned SAH over triangle centroids (up to 16 bins per axis, fewer in small nodes), a binary tree
// first, then collapsed to W children per node by opening the largest child until W are there.
// Large nodes bin and split in parallel; every subtree owns a fixed range of binary-node slots
// (BinaryBuilder::split) and of references, so tasks share nothing and the tree is the same for any
// number of threads.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <bit>

#include "bvh/bvh.h"
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
/// Below this many references a node's work stays on one thread.
constexpr uint32_t parallel_refs = 16384;

struct BinaryNode {
    Bbox3f box;
    uint32_t left = 0, right = 0;   // children (inner nodes)
    uint32_t first = 0, count = 0;  // leaf: range of refs (count > 0)
};

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
/// gather through an index). Lane 3 of lo holds the triangle's index, of hi 0.
struct alignas(32) PrimRef {
    alignas(16) float lo[4];
    alignas(16) float hi[4];
    uint32_t id() const { return std::bit_cast<uint32_t>(lo[3]); }
    /// lo + hi, twice the centroid (the index masked out of lane 3).
    RTT_FORCEINLINE vfloat4 centroid2() const {
        const vint4 xyz(_mm_setr_epi32(-1, -1, -1, 0));
        return as_float(as_int(vfloat4::load(lo)) & xyz) + vfloat4::load(hi);
    }
};

/// The bounds of a node's references and of their (doubled) centroids.
struct Extent {
    Box4 box, centroids;
    RTT_FORCEINLINE void add(const PrimRef& r) {
        box.extend(vfloat4::load(r.lo), vfloat4::load(r.hi));
        const vfloat4 c = r.centroid2();
        centroids.extend(c, c);
    }
    void merge(const Extent& o) {
        box.extend(o.box);
        centroids.extend(o.centroids);
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

class BinaryBuilder {
public:
    explicit BinaryBuilder(std::span<const TriangleVerts> tris) : refs_(tris.size()) {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, tris.size(), 4096),
                          [&](const tbb::blocked_range<size_t>& r) {
                              for (size_t i = r.begin(); i < r.end(); ++i) {
                                  const TriangleVerts& t = tris[i];
                                  PrimRef& p = refs_[i];
                                  for (int a = 0; a < 3; ++a) {
                                      p.lo[a] = std::min(std::min(t.v0[a], t.v1[a]), t.v2[a]);
                                      p.hi[a] = std::max(std::max(t.v0[a], t.v1[a]), t.v2[a]);
                                  }
                                  p.lo[3] = std::bit_cast<float>(uint32_t(i));
                                  p.hi[3] = 0.f;
                              }
                          });
    }

    /// The binary tree; node 0 is the root. Slots of refs that ended in a leaf early stay unused.
    large_vector<BinaryNode> build() {
        nodes_.resize(2 * refs_.size() - 1);
        const Extent root = reduce_range<Extent>(
            0, uint32_t(refs_.size()),
            [&](uint32_t lo, uint32_t hi) {
                Extent e;
                for (uint32_t i = lo; i < hi; ++i) e.add(refs_[i]);
                return e;
            },
            [](Extent& a, const Extent& b) { a.merge(b); });
        split(0, 0, uint32_t(refs_.size()), 0, root);
        return std::move(nodes_);
    }
    /// The references in leaf order: a leaf [first, first + count) lists refs [first, ...).
    const large_vector<PrimRef>& refs() const { return refs_; }

private:
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

    /// Moves the references of [first, end) whose bin along `axis` is below `bin` to the front;
    /// returns where the rest start, with both sides' extents.
    uint32_t partition(uint32_t first, uint32_t end, const BinMap& map, int axis, int bin,
                       Extent& left, Extent& right) {
        const auto goes_left = [&](const PrimRef& r) { return map(r.centroid2())[axis] < bin; };
        uint32_t i = first, j = end;
        for (;;) {
            while (i < j && goes_left(refs_[i])) left.add(refs_[i++]);
            while (i < j && !goes_left(refs_[j - 1])) right.add(refs_[--j]);
            if (i >= j) return i;
            std::swap(refs_[i], refs_[j - 1]);
        }
    }

    // Node `index` over refs [first, end) with extent `ext`: a leaf, or split by the cheapest
    // bin boundary. Its subtree owns the slots [index, index + 2 (end - first) - 1): the left
    // child's subtree starts at index + 1, the right one's at index + 2 (mid - first).
    void split(uint32_t index, uint32_t first, uint32_t end, int depth, const Extent& ext) {
        nodes_[index].box = ext.box.box();
        const uint32_t n = end - first;
        const auto make_leaf = [&] {
            nodes_[index].first = first;
            nodes_[index].count = n;
        };
        if (n <= 2) return make_leaf();
        int best_axis = -1, best_bin = 0;
        float best_cost = intersection_cost * blocks_of(n);
        const BinMap map(ext.centroids, bins_for(n));
        // Past sah_depth only halves: the tree (and the traversal's stack) stays shallow
        // whatever the input (bvh_max_depth).
        if (depth < sah_depth) {
            const Bins all = bin_all(first, end, map);
            const float parent = ext.box.half_area();
            for (int a = 0; a < 3; ++a) {
                if (!(ext.centroids.hi[a] - ext.centroids.lo[a] > 0.f)) continue;
                const auto& bb = all.box[size_t(a)];
                const auto& bc = all.count[size_t(a)];
                // Sweep: areas and counts to the right of each boundary, then to the left.
                std::array<float, max_bins> right_area{};
                std::array<uint32_t, max_bins> right_count{};
                Box4 r;
                uint32_t rc = 0;
                for (int b = map.n - 1; b > 0; --b) {
                    r.extend(bb[size_t(b)]);
                    rc += bc[size_t(b)];
                    right_area[size_t(b)] = r.empty() ? 0.f : r.half_area();
                    right_count[size_t(b)] = rc;
                }
                Box4 l;
                uint32_t lc = 0;
                for (int b = 1; b < map.n; ++b) {
                    l.extend(bb[size_t(b - 1)]);
                    lc += bc[size_t(b - 1)];
                    if (lc == 0 || right_count[size_t(b)] == 0) continue;
                    const float cost =
                        traversal_cost +
                        intersection_cost *
                            (l.half_area() * blocks_of(lc) +
                             right_area[size_t(b)] * blocks_of(right_count[size_t(b)])) /
                            parent;
                    if (cost < best_cost) {
                        best_cost = cost;
                        best_axis = a;
                        best_bin = b;
                    }
                }
            }
        }
        uint32_t mid;
        Extent left, right;
        if (best_axis >= 0) {
            mid = partition(first, end, map, best_axis, best_bin, left, right);
        } else if (n <= bvh_leaf_max) {
            return make_leaf();
        } else {  // no useful split (centroids coincide) or too deep: halves by centroid order
            const vfloat4 d = ext.centroids.hi - ext.centroids.lo;
            const int a = d[0] >= d[1] ? (d[0] >= d[2] ? 0 : 2) : (d[1] >= d[2] ? 1 : 2);
            mid = first + n / 2;
            std::nth_element(refs_.begin() + first, refs_.begin() + mid, refs_.begin() + end,
                             [&](const PrimRef& x, const PrimRef& y) {
                                 const float cx = x.centroid2()[a], cy = y.centroid2()[a];
                                 return cx < cy || (cx == cy && x.id() < y.id());
                             });
            for (uint32_t i = first; i < mid; ++i) left.add(refs_[i]);
            for (uint32_t i = mid; i < end; ++i) right.add(refs_[i]);
        }
        const uint32_t li = index + 1, ri = index + 2 * (mid - first);
        nodes_[index].left = li;
        nodes_[index].right = ri;
        if (n >= parallel_refs)
            tbb::parallel_invoke([&] { split(li, first, mid, depth + 1, left); },
                                 [&] { split(ri, mid, end, depth + 1, right); });
        else {
            split(li, first, mid, depth + 1, left);
            split(ri, mid, end, depth + 1, right);
        }
    }

    // Leaves test four triangles at once: the SAH counts blocks of four.
    static float blocks_of(uint32_t n) { return float((n + 3) / 4); }

    large_vector<PrimRef> refs_;
    large_vector<BinaryNode> nodes_;
};

// The leaf child of refs [first, first + count): its triangles appended as blocks of four.
template <int W>
uint32_t leaf_child(std::span<const TriangleVerts> tris, std::span<const PrimRef> refs,
                    uint32_t first, uint32_t count, Bvh<W>& out) {
    const uint32_t block = uint32_t(out.blocks.size()), blocks = (count + 3) / 4;
    for (uint32_t b = 0; b < blocks; ++b) {
        BvhTriangles4 q{};
        for (uint32_t l = 0; l < 4; ++l) {
            const uint32_t k = b * 4 + l;
            const uint32_t id = k < count ? refs[first + k].id() : invalid_triangle;
            const TriangleVerts& t = tris[k < count ? id : refs[first].id()];
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

// Writes the W-wide node for binary node `b` (an inner node) at `out.nodes[index]`.
template <int W>
void collapse(std::span<const TriangleVerts> tris, std::span<const PrimRef> refs,
              const large_vector<BinaryNode>& bin, uint32_t b, uint32_t index, Bvh<W>& out) {
    std::array<uint32_t, W> kids{bin[b].left, bin[b].right};
    uint32_t n = 2;
    while (n < W) {  // open the inner child with the largest surface
        int open = -1;
        float area = -1.f;
        for (uint32_t i = 0; i < n; ++i)
            if (bin[kids[i]].count == 0 && bin[kids[i]].box.half_area() > area) {
                area = bin[kids[i]].box.half_area();
                open = int(i);
            }
        if (open < 0) break;
        const BinaryNode& o = bin[kids[size_t(open)]];
        kids[size_t(open)] = o.left;
        kids[n++] = o.right;
    }
    BvhNode<W> node{};
    node.count = n;
    for (uint32_t i = 0; i < W; ++i)
        for (int a = 0; a < 3; ++a) {
            node.lo[a][i] = i < n ? bin[kids[i]].box.lo[a] : pos_inf;
            node.hi[a][i] = i < n ? bin[kids[i]].box.hi[a] : neg_inf;
        }
    std::array<uint32_t, W> inner{};
    for (uint32_t i = 0; i < n; ++i) {
        const BinaryNode& k = bin[kids[i]];
        if (k.count > 0) {
            node.child[i] = leaf_child(tris, refs, k.first, k.count, out);
        } else {
            inner[i] = uint32_t(out.nodes.size());
            node.child[i] = inner[i];
            out.nodes.emplace_back();
        }
    }
    out.nodes[index] = node;
    for (uint32_t i = 0; i < n; ++i)
        if (bin[kids[i]].count == 0) collapse(tris, refs, bin, kids[i], inner[i], out);
}

}  // namespace

template <int W>
Bvh<W> build_bvh(std::span<const TriangleVerts> triangles) {
    if (triangles.size() >= bvh_max_triangles)
        throw Error("the bvh tracer takes at most 134,217,727 triangles");
    Bvh<W> out;
    if (triangles.empty()) return out;
    BinaryBuilder builder(triangles);
    const large_vector<BinaryNode> bin = builder.build();
    out.padded_bounds = padded_bounds(bin[0].box);
    const std::span<const PrimRef> refs = builder.refs();
    out.blocks.reserve(triangles.size() / 2);
    out.nodes.emplace_back();
    if (bin[0].count > 0) {  // the whole scene is one leaf: a root with one leaf child
        BvhNode<W>& root = out.nodes[0];
        root.count = 1;
        for (int a = 0; a < 3; ++a)
            for (int i = 0; i < W; ++i) {
                root.lo[a][i] = i == 0 ? bin[0].box.lo[a] : pos_inf;
                root.hi[a][i] = i == 0 ? bin[0].box.hi[a] : neg_inf;
            }
        root.child[0] = leaf_child(triangles, refs, 0, bin[0].count, out);
        return out;
    }
    collapse(triangles, refs, bin, 0, 0, out);
    return out;
}

template Bvh<4> build_bvh<4>(std::span<const TriangleVerts>);
template Bvh<8> build_bvh<8>(std::span<const TriangleVerts>);

}  // namespace rtt
