// Binned SAH over triangle centroids (16 bins per axis), a binary tree first, then collapsed to
// W children per node by opening the largest child until W are there. Large nodes bin and
// split in parallel; every subtree owns a fixed range of binary-node slots (BinaryBuilder::split)
// and of references, so tasks share nothing and the tree is the same for any number of threads.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <numeric>

#include "bvh/bvh.h"
#include "rtt/error.h"
#include "trace/trace_ray.h"

namespace rtt {
namespace {

constexpr int bins = 16;
constexpr float traversal_cost = 1.f, intersection_cost = 1.f;
constexpr int sah_depth = 64;
/// Below this many references a node's work stays on one thread.
constexpr uint32_t parallel_refs = 16384;

struct BinaryNode {
    Bbox3f box;
    uint32_t left = 0, right = 0;   // children (inner nodes)
    uint32_t first = 0, count = 0;  // leaf: range of refs (count > 0)
};

/// Per axis, the bounds and counts of the references whose centroid falls in each bin.
struct Bins {
    std::array<std::array<Bbox3f, bins>, 3> box{};
    std::array<std::array<uint32_t, bins>, 3> count{};

    void merge(const Bins& o) {
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < bins; ++b) {
                box[size_t(a)][size_t(b)].extend(o.box[size_t(a)][size_t(b)]);
                count[size_t(a)][size_t(b)] += o.count[size_t(a)][size_t(b)];
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
    explicit BinaryBuilder(std::span<const TriangleVerts> tris)
        : refs_(tris.size()), boxes_(tris.size()), centers_(tris.size()) {
        std::iota(refs_.begin(), refs_.end(), 0u);
        tbb::parallel_for(tbb::blocked_range<size_t>(0, tris.size(), 4096),
                          [&](const tbb::blocked_range<size_t>& r) {
                              for (size_t i = r.begin(); i < r.end(); ++i) {
                                  Bbox3f box;
                                  box.extend(tris[i].v0);
                                  box.extend(tris[i].v1);
                                  box.extend(tris[i].v2);
                                  boxes_[i] = box;
                                  centers_[i] = box.center();
                              }
                          });
    }

    /// The binary tree; node 0 is the root. Slots of refs that ended in a leaf early stay unused.
    std::vector<BinaryNode> build() {
        nodes_.resize(2 * refs_.size() - 1);
        split(0, 0, uint32_t(refs_.size()), 0);
        return std::move(nodes_);
    }
    const std::vector<uint32_t>& refs() const { return refs_; }

private:
    struct Extent {
        Bbox3f box, centers;
    };

    Extent extent(uint32_t first, uint32_t end) const {
        return reduce_range<Extent>(
            first, end,
            [&](uint32_t lo, uint32_t hi) {
                Extent e;
                for (uint32_t i = lo; i < hi; ++i) {
                    e.box.extend(boxes_[refs_[i]]);
                    e.centers.extend(centers_[refs_[i]]);
                }
                return e;
            },
            [](Extent& a, const Extent& b) {
                a.box.extend(b.box);
                a.centers.extend(b.centers);
            });
    }

    Bins bin_all(uint32_t first, uint32_t end, const Bbox3f& cbox) const {
        float lo[3], scale[3];
        for (int a = 0; a < 3; ++a) {
            lo[a] = cbox.lo[a];
            scale[a] = float(bins) / (cbox.hi[a] - lo[a]);
        }
        return reduce_range<Bins>(
            first, end,
            [&](uint32_t from, uint32_t to) {
                Bins out;
                for (uint32_t i = from; i < to; ++i) {
                    const uint32_t r = refs_[i];
                    for (int a = 0; a < 3; ++a) {
                        const size_t b = size_t(bin_of(centers_[r][a], lo[a], scale[a]));
                        out.box[size_t(a)][b].extend(boxes_[r]);
                        ++out.count[size_t(a)][b];
                    }
                }
                return out;
            },
            [](Bins& x, const Bins& y) { x.merge(y); });
    }

    // Node `index` over refs [first, end): a leaf, or split by the cheapest bin boundary. Its
    // subtree owns the slots [index, index + 2 (end - first) - 1): the left child's subtree
    // starts at index + 1, the right one's at index + 2 (mid - first).
    void split(uint32_t index, uint32_t first, uint32_t end, int depth) {
        const Extent ext = extent(first, end);
        const Bbox3f& box = ext.box;
        const Bbox3f& cbox = ext.centers;
        nodes_[index].box = box;
        const uint32_t n = end - first;
        const auto make_leaf = [&] {
            nodes_[index].first = first;
            nodes_[index].count = n;
        };
        if (n <= 2) return make_leaf();
        int best_axis = -1, best_bin = 0;
        float best_cost = intersection_cost * blocks_of(n);
        // Past sah_depth only halves: the tree (and the traversal's stack) stays shallow
        // whatever the input (bvh_max_depth).
        if (depth < sah_depth) {
            const Bins all = bin_all(first, end, cbox);
            for (int a = 0; a < 3; ++a) {
                if (!(cbox.hi[a] - cbox.lo[a] > 0.f)) continue;
                const auto& bb = all.box[size_t(a)];
                const auto& bc = all.count[size_t(a)];
                // Sweep: areas and counts to the right of each boundary, then to the left.
                std::array<float, bins> right_area{};
                std::array<uint32_t, bins> right_count{};
                Bbox3f r;
                uint32_t rc = 0;
                for (int b = bins - 1; b > 0; --b) {
                    r.extend(bb[size_t(b)]);
                    rc += bc[size_t(b)];
                    right_area[size_t(b)] = r.empty() ? 0.f : r.half_area();
                    right_count[size_t(b)] = rc;
                }
                Bbox3f l;
                uint32_t lc = 0;
                const float parent = box.half_area();
                for (int b = 1; b < bins; ++b) {
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
        if (best_axis >= 0) {
            const float lo = cbox.lo[best_axis];
            const float scale = float(bins) / (cbox.hi[best_axis] - lo);
            mid = uint32_t(std::partition(refs_.begin() + first, refs_.begin() + end,
                                          [&](uint32_t r) {
                                              return bin_of(centers_[r][best_axis], lo, scale) <
                                                     best_bin;
                                          }) -
                           refs_.begin());
        } else if (n <= bvh_leaf_max) {
            return make_leaf();
        } else {  // no useful split (centroids coincide) or too deep: halves by centroid order
            const int a = cbox.diagonal().x >= cbox.diagonal().y
                              ? (cbox.diagonal().x >= cbox.diagonal().z ? 0 : 2)
                              : (cbox.diagonal().y >= cbox.diagonal().z ? 1 : 2);
            mid = first + n / 2;
            std::nth_element(refs_.begin() + first, refs_.begin() + mid, refs_.begin() + end,
                             [&](uint32_t x, uint32_t y) {
                                 return centers_[x][a] < centers_[y][a] ||
                                        (centers_[x][a] == centers_[y][a] && x < y);
                             });
        }
        const uint32_t left = index + 1, right = index + 2 * (mid - first);
        nodes_[index].left = left;
        nodes_[index].right = right;
        if (n >= parallel_refs)
            tbb::parallel_invoke([&] { split(left, first, mid, depth + 1); },
                                 [&] { split(right, mid, end, depth + 1); });
        else {
            split(left, first, mid, depth + 1);
            split(right, mid, end, depth + 1);
        }
    }

    // Leaves test four triangles at once: the SAH counts blocks of four.
    static float blocks_of(uint32_t n) { return float((n + 3) / 4); }

    // NaN (0 * inf from a denormal extent, inf - inf from huge coordinates) goes to bin 0,
    // the same in the SAH sweep and the partition.
    static int bin_of(float c, float lo, float scale) {
        const float x = (c - lo) * scale;
        if (!(x >= 0.f)) return 0;
        return x < float(bins - 1) ? int(x) : bins - 1;
    }

    std::vector<uint32_t> refs_;
    std::vector<Bbox3f> boxes_;
    std::vector<Vec3f> centers_;
    std::vector<BinaryNode> nodes_;
};

// The leaf child of refs [first, first + count): its triangles appended as blocks of four.
template <int W>
uint32_t leaf_child(std::span<const TriangleVerts> tris, const std::vector<uint32_t>& refs,
                    uint32_t first, uint32_t count, Bvh<W>& out) {
    const uint32_t block = uint32_t(out.blocks.size()), blocks = (count + 3) / 4;
    for (uint32_t b = 0; b < blocks; ++b) {
        BvhTriangles4 q{};
        for (uint32_t l = 0; l < 4; ++l) {
            const uint32_t k = b * 4 + l;
            const uint32_t id = k < count ? refs[first + k] : invalid_triangle;
            const TriangleVerts& t = tris[k < count ? id : refs[first]];
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
void collapse(std::span<const TriangleVerts> tris, const std::vector<uint32_t>& refs,
              const std::vector<BinaryNode>& bin, uint32_t b, uint32_t index, Bvh<W>& out) {
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
    const std::vector<BinaryNode> bin = builder.build();
    out.padded_bounds = padded_bounds(bin[0].box);
    const std::vector<uint32_t>& refs = builder.refs();
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
