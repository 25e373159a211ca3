#include "kdtree/kd_small_build.h"

#include <algorithm>
#include <cstdint>
#include <new>

#include "kdtree/kd_clip.h"

namespace rtt::kd {

namespace {

/// Candidate planes counted at once, one per SIMD lane.
constexpr size_t lanes = 16;
constexpr size_t max_candidates = 2 * small_max_triangles;

}  // namespace

SplitChoice find_small_split(std::span<const TriBox> items, const Bbox3f& box,
                             const KdBuildConfig& config) {
    const size_t n = items.size();
    SplitChoice best;
    const Vec3f diag = box.diagonal();
    const double area = double(diag.x) * diag.y + double(diag.y) * diag.z + double(diag.z) * diag.x;
    if (!(area > 0.0)) return best;  // as AxisCost::has_area
    const double inv_area = 1.0 / area, bonus = 1.0 - double(config.empty_bonus);
    const double trav = config.trav_cost, isect = config.isect_cost;

    // Structure of arrays, candidates in lanes, so that the loops below vectorise.
    alignas(64) float lo[small_max_triangles], hi[small_max_triangles], cand[max_candidates];
    alignas(64) uint32_t below[max_candidates], above[max_candidates], planar[max_candidates];
    alignas(64) double cost_left[max_candidates], cost_right[max_candidates];
    for (int a = 0; a < 3; ++a) {
        size_t m = 0;
        for (size_t i = 0; i < n; ++i) {
            lo[i] = items[i].box.lo[a] + 0.f;  // + 0: -0 becomes 0, as in the events
            hi[i] = items[i].box.hi[a] + 0.f;
            cand[m++] = lo[i];
            if (hi[i] != lo[i]) cand[m++] = hi[i];  // a flat triangle has one event
        }
        const size_t padded = (m + lanes - 1) / lanes * lanes;
        for (size_t c = m; c < padded; ++c) cand[c] = cand[0];
        // below: lo < p, above: hi > p, planar: flat in p (the sweep's counts at p).
        for (size_t c0 = 0; c0 < padded; c0 += lanes) {
            uint32_t b[lanes] = {}, ab[lanes] = {}, pl[lanes] = {};
            for (size_t j = 0; j < n; ++j) {
                const float l = lo[j], h = hi[j];
                for (size_t k = 0; k < lanes; ++k) {
                    const float p = cand[c0 + k];
                    b[k] += l < p;
                    ab[k] += h > p;
                    pl[k] += (l == p) & (h == p);
                }
            }
            for (size_t k = 0; k < lanes; ++k) {
                below[c0 + k] = b[k];
                above[c0 + k] = ab[k];
                planar[c0 + k] = pl[k];
            }
        }
        // AxisCost's formula, for planar triangles left and right.
        const double box_lo = box.lo[a], box_hi = box.hi[a];
        const double d1 = diag[(a + 1) % 3], d2 = diag[(a + 2) % 3];
        const double cap = d1 * d2, perimeter = d1 + d2;
        const double nd = double(n);
        // Branch-free (bitwise & and |), so that it vectorises.
        for (size_t c = 0; c < padded; ++c) {
            const double p = cand[c];
            const double pl_area = (cap + (p - box_lo) * perimeter) * inv_area;
            const double pr_area = (cap + (box_hi - p) * perimeter) * inv_area;
            const double b = int32_t(below[c]), ab = int32_t(above[c]), fl = int32_t(planar[c]);
            const auto cost = [&](double cl, double cr) {
                const double c0 = trav + isect * (pl_area * cl + pr_area * cr);
                const bool no_progress =
                    ((p == box_hi) & (cl == nd)) | ((p == box_lo) & (cr == nd));
                const double factor = ((cl == 0.0) | (cr == 0.0)) ? bonus : 1.0;
                return no_progress ? pos_inf : c0 * factor;
            };
            cost_left[c] = cost(b + fl, ab);
            const double right = cost(b, ab + fl);
            cost_right[c] = fl > 0.0 ? right : pos_inf;
        }
        // The cheapest cost, lane by lane so that it vectorises; then the sweep's choice among
        // the candidates of that cost: it visits planes in increasing order, planar triangles
        // left first, and keeps the first cheapest.
        constexpr size_t width = 8;
        double lane_min[width];
        for (size_t k = 0; k < width; ++k) lane_min[k] = pos_inf;
        for (size_t c0 = 0; c0 < padded; c0 += width)
            for (size_t k = 0; k < width; ++k) {
                const double l = cost_left[c0 + k], r = cost_right[c0 + k];
                const double lr = r < l ? r : l;
                lane_min[k] = lr < lane_min[k] ? lr : lane_min[k];
            }
        double cheapest = pos_inf;
        for (double v : lane_min) cheapest = v < cheapest ? v : cheapest;
        if (cheapest == pos_inf) continue;
        // The lowest plane of that cost (lane by lane again), then whether planar left does it.
        float lane_p[width];
        for (size_t k = 0; k < width; ++k) lane_p[k] = pos_inf;
        for (size_t c0 = 0; c0 < padded; c0 += width)
            for (size_t k = 0; k < width; ++k) {
                const size_t c = c0 + k;
                const bool hit = (cost_left[c] == cheapest) | (cost_right[c] == cheapest);
                const float p = hit ? cand[c] : pos_inf;
                lane_p[k] = p < lane_p[k] ? p : lane_p[k];
            }
        float lowest = pos_inf;
        for (float p : lane_p) lowest = p < lowest ? p : lowest;
        size_t at = m;  // a candidate at `lowest` of that cost, planar left if one is
        for (size_t c = 0; c < m; ++c)
            if (cand[c] == lowest) {
                if (cost_left[c] == cheapest) {
                    at = c;
                    break;
                }
                if (cost_right[c] == cheapest && at == m) at = c;
            }
        const bool planar_left = cost_left[at] == cheapest;
        const uint32_t fl = planar[at];
        const SplitChoice axis_best{a,
                                    cand[at],
                                    planar_left,
                                    cheapest,
                                    below[at] + (planar_left ? fl : 0),
                                    above[at] + (planar_left ? 0 : fl)};
        best = better(best, axis_best);
    }
    return best;
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

}  // namespace rtt::kd
