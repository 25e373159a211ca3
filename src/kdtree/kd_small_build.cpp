#include "kdtree/kd_small_build.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>
#include <new>

#include "kdtree/kd_clip.h"
#include "rtt/isa.h"
#include "simd/isa.h"

namespace rtt {

// The split search of each ISA's kernels (kd_small_split.cpp, compiled once per ISA). This
// file's own ISA namespace is inline (simd/isa.h), and is reopened as one.
#define RTT_DECLARE_SMALL_SPLIT(inline_or_not, isa)                                     \
    inline_or_not namespace isa {                                                       \
        kd::SplitChoice kd_find_small_split(std::span<const kd::TriBox>, const Bbox3f&, \
                                            const KdBuildConfig&);                      \
    }
RTT_DECLARE_SMALL_SPLIT(inline, RTT_ISA_NS)
#ifdef RTT_KERNELS_AVX2
RTT_DECLARE_SMALL_SPLIT(, isa_avx2)
#endif
#ifdef RTT_KERNELS_AVX512
RTT_DECLARE_SMALL_SPLIT(, isa_avx512)
#endif
#undef RTT_DECLARE_SMALL_SPLIT

namespace kd {

SplitChoice find_small_split(std::span<const TriBox> items, const Bbox3f& box,
                             const KdBuildConfig& config) {
    switch (active_isa()) {
#ifdef RTT_KERNELS_AVX512
        case Isa::avx512:
            return isa_avx512::kd_find_small_split(items, box, config);
#endif
#ifdef RTT_KERNELS_AVX2
        case Isa::avx2:
            return isa_avx2::kd_find_small_split(items, box, config);
#endif
        default:
            return RTT_ISA_NS::kd_find_small_split(items, box, config);
    }
}

void SmallBuilder::build(std::span<const TriBox> items, const Bbox3f& box, int depth, double budget,
                         Subtree& out) const {
    std::vector<TriBox> stack;
    stack.reserve(8 * small_max_triangles);
    stack.assign(items.begin(), items.end());
    build_top(stack, items.size(), box, depth, budget, out);
}

void SmallBuilder::build_top(std::vector<TriBox>& stack, size_t n, const Bbox3f& box, int depth,
                             double budget, Subtree& out) const {
    const size_t begin = stack.size() - n;
    SplitChoice split;
    if (n > size_t(config_.max_leaf_size) && depth < max_depth_)
        split = find_small_split({stack.data() + begin, n}, box, config_);
    if (!takes_split(split, n, budget, config_)) {
        const size_t first = out.leaf_triangles.size();
        for (size_t i = begin; i < begin + n; ++i) out.leaf_triangles.push_back(stack[i].tri);
        out.add_leaf(first);
        stack.resize(begin);
        return;
    }
    Bbox3f left_box = box, right_box = box;
    left_box.hi[split.axis] = split.pos;
    right_box.lo[split.axis] = split.pos;

    // The children's items, the above child's first so that the below child ends the stack.
    // The binned levels' rule (kd_build.cpp): a triangle touching the plane goes to the side it
    // lies on, one lying in it to pside, one crossing it is clipped to each child.
    const int a = split.axis;
    const float p = split.pos;
    enum : uint8_t { left = 1, right = 2 };
    uint8_t sides[small_max_triangles];
    // Uninitialised slots: a node clips a few of its triangles, and default-constructing 64
    // boxes per node would cost more than that.
    union Slot {
        Slot() {}
        ClippedSides c;
    } slots[small_max_triangles];
    ClippedSides* clipped = &slots[0].c;
    size_t straddlers = 0;
    for (size_t i = 0; i < n; ++i) {
        const TriBox& t = stack[begin + i];
        const float lo = t.box.lo[a], hi = t.box.hi[a];
        if (lo == hi) {
            sides[i] = lo < p || (lo == p && split.planar_left) ? left : right;
        } else if (hi <= p) {
            sides[i] = left;
        } else if (lo >= p) {
            sides[i] = right;
        } else {
            const ClippedSides& c = *new (&slots[straddlers++].c) ClippedSides(
                clip_triangle_to_children(triangles_[t.tri], box, a, p));
            sides[i] = uint8_t((c.left ? left : 0) | (c.right ? right : 0)) | 4u;  // 4: clipped
        }
    }
    stack.reserve(begin + 3 * n);  // no reallocation below: at most 2n children's items
    for (size_t i = 0, c = 0; i < n; ++i) {
        const TriBox& t = stack[begin + i];
        if (sides[i] & 4u) {
            if (clipped[c].right) stack.push_back({clipped[c].right_box, t.tri});
            ++c;
        } else if (sides[i] == right) {
            stack.push_back(t);
        }
    }
    const size_t right_begin = begin + n, left_begin = stack.size();
    for (size_t i = 0, c = 0; i < n; ++i) {
        const TriBox& t = stack[begin + i];
        if (sides[i] & 4u) {
            if (clipped[c].left) stack.push_back({clipped[c].left_box, t.tri});
            ++c;
        } else if (sides[i] == left) {
            stack.push_back(t);
        }
    }
    const size_t n_right = left_begin - right_begin, n_left = stack.size() - left_begin;

    const size_t index = out.begin_inner();
    build_top(stack, n_left, left_box, depth + 1, child_budget(budget, split, true), out);
    out.end_inner(index, split);
    build_top(stack, n_right, right_box, depth + 1, child_budget(budget, split, false), out);
    stack.resize(begin);
}

}  // namespace kd
}  // namespace rtt
