#include "kdtree/kd_binned_sah.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace rtt::kd {
namespace {

constexpr int planes = binned_planes;

/// Per axis, over the planes b_1 < ... < b_K: triangles whose lo has exactly k planes <= it,
/// whose hi has exactly k planes < it, and flat ones lying in plane k. Then #{lo < b_k} is the
/// sum of the first k lo counts, #{hi > b_k} the sum of the hi counts from k on.
struct Bins {
    std::array<std::array<uint32_t, planes + 1>, 3> lo{}, hi{}, flat{};

    void add(const Bins& o) {
        for (int a = 0; a < 3; ++a)
            for (int k = 0; k <= planes; ++k) {
                lo[a][k] += o.lo[a][k];
                hi[a][k] += o.hi[a][k];
                flat[a][k] += o.flat[a][k];
            }
    }
};

/// The planes of one axis: their positions, and a fast exact count of the planes below a value.
struct AxisPlanes {
    std::array<float, planes + 2> pos;  ///< pos[1..planes]; pos[0] = -inf, pos[planes+1] = +inf
    float lo = 0.f, scale = 0.f;

    /// Evenly spaced planes strictly inside (lo, hi), strictly increasing; false when the box
    /// is too thin along the axis to hold them.
    bool init(float box_lo, float box_hi) {
        lo = box_lo;
        scale = float(planes + 1) / (box_hi - box_lo);
        pos[0] = neg_inf;
        pos[planes + 1] = pos_inf;
        for (int k = 1; k <= planes; ++k) {
            pos[k] = float(double(box_lo) + (double(box_hi) - double(box_lo)) * k / (planes + 1));
            if (!(pos[k] > (k == 1 ? box_lo : pos[k - 1]) && pos[k] < box_hi)) return false;
        }
        return std::isfinite(scale);
    }

    /// Number of planes <= x (or < x when `strict`): an estimate, corrected against the
    /// planes themselves so it is exact.
    int count_below(float x, bool strict) const {
        int k = int(std::clamp((x - lo) * scale, 0.f, float(planes)));
        const auto below = [&](int j) { return strict ? pos[j] < x : pos[j] <= x; };
        while (k < planes && below(k + 1)) ++k;
        while (k > 0 && !below(k)) --k;
        return k;
    }
};

}  // namespace

SplitChoice find_binned_split(std::span<const TriBox> items, const Bbox3f& box,
                              const KdBuildConfig& config) {
    SplitChoice best;
    AxisPlanes axes[3];
    for (int a = 0; a < 3; ++a)
        if (!axes[a].init(box.lo[a], box.hi[a])) return best;

    const Bins bins = tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, items.size(), 4096), Bins{},
        [&](const tbb::blocked_range<size_t>& r, Bins b) {
            for (size_t i = r.begin(); i < r.end(); ++i)
                for (int a = 0; a < 3; ++a) {
                    const float lo = items[i].box.lo[a], hi = items[i].box.hi[a];
                    const int k_lo = axes[a].count_below(lo, false);
                    ++b.lo[a][k_lo];
                    ++b.hi[a][axes[a].count_below(hi, true)];
                    if (lo == hi && k_lo > 0 && axes[a].pos[k_lo] == lo) ++b.flat[a][k_lo];
                }
            return b;
        },
        [](Bins x, const Bins& y) {
            x.add(y);
            return x;
        });

    const size_t n = items.size();
    for (int a = 0; a < 3; ++a) {
        const AxisCost cost(a, box, n, config);
        if (!cost.has_area()) return best;
        size_t below = 0, above = n;  // #{lo < b_k}, #{hi > b_k}
        for (int k = 1; k <= planes; ++k) {
            below += bins.lo[a][k - 1];
            above -= bins.hi[a][k - 1];
            const float p = axes[a].pos[k];
            const size_t planar = bins.flat[a][k];
            // The sweep's counts at p: flat triangles in p are on neither side yet.
            const auto consider = [&](size_t cl, size_t cr, bool planar_left) {
                const double c = cost(p, cl, cr);
                if (c < best.cost) best = {a, p, planar_left, c, cl, cr};
            };
            consider(below + planar, above, true);
            if (planar > 0) consider(below, above + planar, false);
        }
    }
    return best;
}

}  // namespace rtt::kd
