#include "kdtree/kd_binned_sah.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "core/float_step.h"
#include "simd/simd.h"

namespace rtt::kd {
namespace {

constexpr int max_planes = 255;

/// Triangles per task when a large node counts its triangles.
constexpr size_t grain = 8192;

/// The planes of one axis. A value's bin is its scaled offset rounded down, and plane k is the
/// least float whose bin is k: the bin then IS the count of planes <= the value, exactly, with
/// no search and no correction (the bin is monotone in the value, since float subtraction and
/// multiplication round monotonically). The count of planes < x is the bin of the float before
/// x. A plane's exact position is only searched for where a split may be placed (exact());
/// costs are compared at the even spacing (approx()), a few floats away.
struct AxisPlanes {
    int planes = 0;
    float lo = 0.f, hi = 0.f, scale = 0.f;

    /// Number of planes <= x.
    int bin(float x) const { return int(std::clamp((x - lo) * scale, 0.f, float(planes))); }
    /// Number of planes < x.
    int bin_strict(float x) const { return bin(next_float_down(x)); }

    /// False when the box is too thin along the axis for the planes.
    bool init(float box_lo, float box_hi, int k_planes) {
        planes = k_planes;
        lo = box_lo;
        hi = box_hi;
        scale = float(planes + 1) / (box_hi - box_lo);
        return std::isfinite(scale) && scale > 0.f && bin(box_hi) >= planes;
    }

    /// Plane k (1 <= k <= planes) at the even spacing.
    float approx(int k) const {
        return std::clamp(float(double(lo) + (double(hi) - double(lo)) * k / (planes + 1)), lo, hi);
    }

    /// Plane k's position: the least float in (lo, hi] of bin >= k; -inf for k = 0, +inf for
    /// k = planes + 1. Searched from approx(k): a few floats away, except near 0, where floats
    /// are dense and a bin spans millions of them; so the search gallops, then bisects (in the
    /// floats' order).
    float exact(int k) const {
        if (k <= 0) return neg_inf;
        if (k > planes) return pos_inf;
        const auto in_bin = [&](uint32_t key) { return bin(float_from_order_key(key)) >= k; };
        const uint32_t first = float_order_key(lo), last = float_order_key(hi);
        uint32_t below = float_order_key(approx(k)), above = below;  // bin < k / >= k
        if (in_bin(above)) {
            for (uint64_t step = 1; below > first && in_bin(below); step *= 2) {
                above = below;
                below = below - first > step ? below - uint32_t(step) : first;
            }
        } else {
            for (uint64_t step = 1; !in_bin(above); step *= 2) {
                below = above;
                above = last - above > step ? above + uint32_t(step) : last;
            }
        }
        while (above - below > 1) {
            const uint32_t middle = below + (above - below) / 2;
            (in_bin(middle) ? above : below) = middle;
        }
        return float_from_order_key(above);
    }
};

/// Per axis, over the planes b_1 < ... < b_K: triangles whose lo has exactly k planes <= it,
/// whose hi has exactly k planes < it, and flat ones lying in plane k. Then #{lo < b_k} is the
/// sum of the first k lo counts, #{hi > b_k} the sum of the hi counts from k on.
struct Bins {
    int planes = 0;
    std::vector<uint32_t> counts;  ///< [axis][lo, hi, flat][planes + 1]

    explicit Bins(int k = 0) : planes(k), counts(size_t(9) * size_t(k + 1), 0u) {}
    uint32_t* at(int axis, int kind) {
        return counts.data() + size_t(axis * 3 + kind) * size_t(planes + 1);
    }
    const uint32_t* at(int axis, int kind) const {
        return counts.data() + size_t(axis * 3 + kind) * size_t(planes + 1);
    }
    void add(const Bins& o) {
        for (size_t i = 0; i < counts.size(); ++i) counts[i] += o.counts[i];
    }
};

/// The bins of a node's triangle bounds, the three axes in SIMD lanes; the lanes compute
/// exactly AxisPlanes::bin and bin_strict.
class Binner {
public:
    explicit Binner(const AxisPlanes (&axes)[3])
        : lo_origin_(vfloat4::setr(axes[0].lo, axes[1].lo, axes[2].lo, 0.f)),
          lo_scale_(vfloat4::setr(axes[0].scale, axes[1].scale, axes[2].scale, 0.f)),
          // hi is loaded from lo.z on (lanes lo.z, hi.x, hi.y, hi.z): the load stays inside the
          // TriBox, and no lane reads the triangle index as a float.
          hi_origin_(vfloat4::setr(0.f, axes[0].lo, axes[1].lo, axes[2].lo)),
          hi_scale_(vfloat4::setr(0.f, axes[0].scale, axes[1].scale, axes[2].scale)),
          top_(float(axes[0].planes)) {}

    /// k_lo[a] = planes <= lo[a] (lanes 0-2), k_hi[a + 1] = planes < hi[a] (lanes 1-3).
    void bins(const TriBox& t, int32_t (&k_lo)[4], int32_t (&k_hi)[4]) const {
        static_assert(sizeof(Bbox3f) == 6 * sizeof(float) && offsetof(TriBox, box) == 0);
        const float* box = reinterpret_cast<const float*>(&t.box);
        const vfloat4 lo = vfloat4::loadu(box), hi = vfloat4::loadu(box + 2);
        storeu(k_lo, bin(lo, lo_origin_, lo_scale_));
        storeu(k_hi, bin(float_before(hi), hi_origin_, hi_scale_));
    }

private:
    vint4 bin(vfloat4 x, vfloat4 origin, vfloat4 scale) const {
        return truncate_to_int(min(max((x - origin) * scale, vfloat4(0.f)), top_));
    }
    /// next_float_down, lane by lane.
    static vfloat4 float_before(vfloat4 x) {
        const vint4 bits = as_int(x + vfloat4(0.f)), zero(0);
        const vint4 up = select(bits < zero, bits + vint4(1), vint4(int32_t(0x80000001u)));
        return as_float(select(bits > zero, bits - vint4(1), up));
    }

    vfloat4 lo_origin_, lo_scale_, hi_origin_, hi_scale_, top_;
};

void count(std::span<const TriBox> items, const AxisPlanes (&axes)[3], Bins& b) {
    const Binner binner(axes);
    uint32_t* lo_bins[3] = {b.at(0, 0), b.at(1, 0), b.at(2, 0)};
    uint32_t* hi_bins[3] = {b.at(0, 1), b.at(1, 1), b.at(2, 1)};
    uint32_t* flat_bins[3] = {b.at(0, 2), b.at(1, 2), b.at(2, 2)};
    for (const TriBox& t : items) {
        int32_t k_lo[4], k_hi[4];
        binner.bins(t, k_lo, k_hi);
        for (int a = 0; a < 3; ++a) {
            ++lo_bins[a][k_lo[a]];
            ++hi_bins[a][k_hi[a + 1]];
            // Flat in a plane: lo is a plane's position exactly when the float before it has a
            // lower bin.
            if (t.box.lo[a] == t.box.hi[a] && k_hi[a + 1] != k_lo[a]) ++flat_bins[a][k_lo[a]];
        }
    }
}

/// The sweep over the triangle bounds strictly between `from` and `to` on axis `a`, with exact
/// counts (Wald & Havran 2006, Algorithm 4, started part-way): the planes between two binned
/// planes, or every plane when from = -inf and to = +inf.
SplitChoice sweep_between(std::span<const TriBox> items, int a, float from, float to,
                          const AxisCost& cost, EventList& events) {
    events.clear();
    size_t n_left = 0, n_right = 0;  // lo <= from; hi >= to (+ those ending inside, below)
    for (const TriBox& t : items) {
        const float lo = t.box.lo[a], hi = t.box.hi[a];
        n_left += lo <= from;
        n_right += hi >= to;
        const bool lo_in = lo > from && lo<to, hi_in = hi> from && hi < to;
        if (lo == hi) {
            if (lo_in) events.emplace_back(lo, EventType::planar, 0);
        } else {
            if (lo_in) events.emplace_back(lo, EventType::start, 0);
            if (hi_in) events.emplace_back(hi, EventType::end, 0);
        }
    }
    std::sort(events.begin(), events.end());
    for (const Event& e : events) n_right += e.type() != EventType::start;

    SplitChoice best;
    const size_t count = events.size();
    for (size_t i = 0; i < count;) {
        const float p = events[i].pos;
        size_t ending = 0, planar = 0, starting = 0;
        while (i < count && events[i].pos == p && events[i].type() == EventType::end) ++ending, ++i;
        while (i < count && events[i].pos == p && events[i].type() == EventType::planar)
            ++planar, ++i;
        while (i < count && events[i].pos == p && events[i].type() == EventType::start)
            ++starting, ++i;
        n_right -= planar + ending;
        const auto consider = [&](size_t cl, size_t cr, bool planar_left) {
            const double c = cost(p, cl, cr);
            if (c < best.cost) best = {a, p, planar_left, c, cl, cr};
        };
        consider(n_left + planar, n_right, true);
        if (planar > 0) consider(n_left, n_right + planar, false);
        n_left += starting + planar;
    }
    return best;
}

/// The better of two choices on one axis; at equal cost the lower plane, planar left first
/// (the one the sweep meets first).
SplitChoice first_cheapest(const SplitChoice& x, const SplitChoice& y) {
    if (x.axis < 0) return y;
    if (y.axis < 0) return x;
    if (x.cost != y.cost) return y.cost < x.cost ? y : x;
    return y.pos < x.pos || (y.pos == x.pos && y.planar_left && !x.planar_left) ? y : x;
}

}  // namespace

SplitChoice find_exact_split(std::span<const TriBox> items, const Bbox3f& box,
                             const KdBuildConfig& config) {
    SplitChoice best;
    EventList events;
    for (int a = 0; a < 3; ++a) {
        const AxisCost cost(a, box, items.size(), config);
        if (!cost.has_area()) return best;
        best = better(best, sweep_between(items, a, neg_inf, pos_inf, cost, events));
    }
    return best;
}

int binned_planes_for(size_t n) {
    return n < 512 ? 31 : n < 2048 ? 63 : n < 8192 ? 127 : max_planes;
}

SplitChoice find_binned_split(std::span<const TriBox> items, const Bbox3f& box,
                              const KdBuildConfig& config) {
    SplitChoice best;
    const size_t n = items.size();
    EventList events;
    events.reserve(64);
    const int planes = binned_planes_for(n);
    AxisPlanes axes[3];
    bool binned = true;
    for (int a = 0; a < 3; ++a) binned &= axes[a].init(box.lo[a], box.hi[a], planes);
    if (!binned) return find_exact_split(items, box, config);  // too thin for the planes

    Bins bins(planes);
    if (n < 2 * grain) {
        count(items, axes, bins);
    } else {
        bins = tbb::parallel_reduce(
            tbb::blocked_range<size_t>(0, n, grain), Bins(planes),
            [&](const tbb::blocked_range<size_t>& r, Bins b) {
                count(items.subspan(r.begin(), r.size()), axes, b);
                return b;
            },
            [](Bins x, const Bins& y) {
                x.add(y);
                return x;
            });
    }

    SplitChoice axis_best[3];
    int k_best[3] = {0, 0, 0};
    for (int a = 0; a < 3; ++a) {
        const AxisCost cost(a, box, n, config);
        if (!cost.has_area()) return best;
        const uint32_t *lo_bins = bins.at(a, 0), *hi_bins = bins.at(a, 1), *flat = bins.at(a, 2);
        size_t below = 0, above = n;  // #{lo < b_k}, #{hi > b_k}
        for (int k = 1; k <= planes; ++k) {
            below += lo_bins[k - 1];
            above -= hi_bins[k - 1];
            const float p = axes[a].approx(k);
            const size_t planar = flat[k];
            // The sweep's counts at p: flat triangles in p are on neither side yet.
            const auto consider = [&](size_t cl, size_t cr, bool planar_left) {
                const double c = cost(p, cl, cr);
                if (c < axis_best[a].cost) {
                    axis_best[a] = {a, p, planar_left, c, cl, cr};
                    k_best[a] = k;
                }
            };
            consider(below + planar, above, true);
            if (planar > 0) consider(below, above + planar, false);
        }
    }
    // A refinement scans all the node's triangles, and rarely moves the choice to another axis:
    // only the axis of the cheapest binned plane is refined, and only it can be chosen
    // (docs/benchmarks.md, "kd-tree build").
    const double cheapest = std::min({axis_best[0].cost, axis_best[1].cost, axis_best[2].cost});
    for (int a = 0; a < 3; ++a) {
        if (axis_best[a].axis < 0 || axis_best[a].cost != cheapest) continue;
        const AxisCost cost(a, box, n, config);
        const AxisPlanes& axis = axes[a];
        const int k = k_best[a];
        // The bins counted at the plane's exact position, so the split is placed and costed there.
        SplitChoice binned = axis_best[a];
        binned.pos = axis.exact(k);
        if (!(binned.pos > axis.lo && binned.pos < axis.hi))
            return find_exact_split(items, box, config);  // too thin for the planes
        binned.cost = cost(binned.pos, binned.left_count, binned.right_count);
        if (binned.cost == pos_inf) binned.axis = -1;
        // The exact planes between the binned planes around the best one.
        const SplitChoice near =
            sweep_between(items, a, axis.exact(k - 1), axis.exact(k + 1), cost, events);
        best = better(best, first_cheapest(binned, near));
    }
    return best;
}

}  // namespace rtt::kd
