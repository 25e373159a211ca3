// The small nodes' split search (kd_small_build.h), a SIMD kernel compiled once per ISA
// (simd/isa.h): its counts are integers and its costs the same IEEE operations at any width, so
// every ISA picks the same plane and the tree does not depend on the CPU.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>
#include <new>

#include "kdtree/kd_small_build.h"
#include "simd/simd.h"

namespace rtt {
inline namespace RTT_ISA_NS {

using namespace rtt::kd;

namespace {

/// Candidate planes counted at once, one per SIMD lane.
constexpr size_t lanes = 16;
constexpr size_t max_candidates = 2 * small_max_triangles;

/// The sweep's counts at each candidate p (padded to whole blocks of lanes): below, lo < p;
/// above, hi > p; planar, flat == p (`flat` is NaN where a triangle is not flat, so that one
/// comparison counts it), only where the node has flat triangles: most have none on an axis.
/// Written as selects, the increments become masked adds with AVX-512.
template <bool count_planar>
void count_sides(const float* lo, const float* hi, const float* flat, size_t n, const float* cand,
                 size_t padded, uint32_t* below, uint32_t* above, uint32_t* planar) {
    for (size_t c0 = 0; c0 < padded; c0 += lanes) {
        uint32_t b[lanes] = {}, ab[lanes] = {}, pl[lanes] = {};
        for (size_t j = 0; j < n; ++j) {
            const float l = lo[j], h = hi[j], f = flat[j];
            // Without the planar count GCC 12 would unroll this loop fully and not vectorise it.
#pragma GCC unroll 1
            for (size_t k = 0; k < lanes; ++k) {
                const float p = cand[c0 + k];
                b[k] = l < p ? b[k] + 1 : b[k];
                ab[k] = h > p ? ab[k] + 1 : ab[k];
                if constexpr (count_planar) pl[k] = f == p ? pl[k] + 1 : pl[k];
            }
        }
        for (size_t k = 0; k < lanes; ++k) {
            below[c0 + k] = b[k];
            above[c0 + k] = ab[k];
            planar[c0 + k] = pl[k];
        }
    }
}

}  // namespace

SplitChoice kd_find_small_split(std::span<const TriBox> items, const Bbox3f& box,
                                const KdBuildConfig& config) {
    const size_t n = items.size();
    SplitChoice best;
    const Vec3f diag = box.diagonal();
    const double area = double(diag.x) * diag.y + double(diag.y) * diag.z + double(diag.z) * diag.x;
    if (!(area > 0.0)) return best;  // as AxisCost::has_area
    const double inv_area = 1.0 / area, bonus = 1.0 - double(config.empty_bonus);
    const double trav = config.trav_cost, isect = config.isect_cost;

    // Structure of arrays, candidates in lanes, so that the loops below vectorise.
    alignas(64) float lo[small_max_triangles], hi[small_max_triangles], flat[small_max_triangles];
    alignas(64) float cand[max_candidates], approx[max_candidates];
    alignas(64) uint32_t below[max_candidates], above[max_candidates], planar[max_candidates];
    constexpr float nan = std::numeric_limits<float>::quiet_NaN();
    for (int a = 0; a < 3; ++a) {
        size_t m = 0, flats = 0;
        // A start at the node's lower face or an end at its upper face (what clipping leaves
        // on most straddlers) puts every triangle on one side but the flat ones, whose own
        // events are candidates: such a plane makes no progress (AxisCost), so it is skipped.
        const float face_lo = box.lo[a], face_hi = box.hi[a];
        for (size_t i = 0; i < n; ++i) {
            lo[i] = items[i].box.lo[a] + 0.f;  // + 0: -0 becomes 0, as in the events
            hi[i] = items[i].box.hi[a] + 0.f;
            const bool is_flat = hi[i] == lo[i];  // a flat triangle has one event
            cand[m] = lo[i];  // written always, kept by the count: no branch to mispredict
            m += is_flat || lo[i] != face_lo;
            cand[m] = hi[i];
            m += !is_flat && hi[i] != face_hi;
            flat[i] = is_flat ? lo[i] : nan;
            flats += is_flat;
        }
        if (m == 0) continue;
        const size_t padded = (m + lanes - 1) / lanes * lanes;
        for (size_t c = m; c < padded; ++c) cand[c] = cand[0];
        if (flats > 0)
            count_sides<true>(lo, hi, flat, n, cand, padded, below, above, planar);
        else
            count_sides<false>(lo, hi, flat, n, cand, padded, below, above, planar);
        // The exact cost (AxisCost, in double) only for the few candidates that can be the
        // cheapest.
        const AxisCost exact_cost(a, box, n, config);
        const double d1 = diag[(a + 1) % 3], d2 = diag[(a + 2) % 3];
        const double cap = d1 * d2, perimeter = d1 + d2;
        // Which ones: the same costs in float, 16 lanes at a time, branch-free so that it
        // vectorises. The items lie in the node's box, so every term is non-negative and each
        // float cost is within a relative 1e-6 of the exact one, unless the area ratios overflow
        // a float or the costs are near its smallest normal numbers: then all are candidates.
        const double perimeter_ratio = perimeter * inv_area;
        const bool approx_holds = perimeter_ratio < 1e30 && trav * bonus > 1e-30;
        const float cap_f = float(cap * inv_area), perimeter_f = float(perimeter_ratio);
        const float lo_f = box.lo[a], hi_f = box.hi[a], n_f = float(n);
        const float trav_f = float(trav), isect_f = float(isect), bonus_f = float(bonus);
        for (size_t c0 = 0; c0 < padded; c0 += lanes)
            for (size_t k = 0; k < lanes; ++k) {
                const size_t c = c0 + k;
                const float p = cand[c];
                const float pl_area = cap_f + (p - lo_f) * perimeter_f;
                const float pr_area = cap_f + (hi_f - p) * perimeter_f;
                const float b = float(int32_t(below[c])), ab = float(int32_t(above[c]));
                const float fl = float(int32_t(planar[c]));
                const auto cost = [&](float cl, float cr) {
                    const float c0 = trav_f + isect_f * (pl_area * cl + pr_area * cr);
                    const bool no_progress =
                        ((p == hi_f) & (cl == n_f)) | ((p == lo_f) & (cr == n_f));
                    const float factor = ((cl == 0.f) | (cr == 0.f)) ? bonus_f : 1.f;
                    return no_progress ? pos_inf : c0 * factor;
                };
                const float l = cost(b + fl, ab), right = cost(b, ab + fl);
                const float r = fl > 0.f ? right : pos_inf;
                const float lr = r < l ? r : l;
                approx[c] = lr;
            }
        using vfloat_max = vfloat<simd_max_width>;
        vfloat_max lane_min = pos_inf;
        for (size_t c0 = 0; c0 < padded; c0 += simd_max_width)
            lane_min = min(lane_min, vfloat_max::load(approx + c0));
        const float approx_min = reduce_min(lane_min)[0];
        if (approx_holds && approx_min == pos_inf) continue;  // no split makes progress
        const float near = approx_min * 1.0001f;
        const uint32_t all_lanes = approx_holds ? 0u : (1u << simd_max_width) - 1u;

        // The sweep's choice among them: it visits planes in increasing order, planar triangles
        // left first, and keeps the first cheapest.
        SplitChoice axis_best;
        for (size_t c0 = 0; c0 < padded; c0 += simd_max_width)
            for (uint32_t near_bits =
                     movemask(vfloat_max::load(approx + c0) <= vfloat_max(near)) | all_lanes;
                 near_bits != 0; near_bits &= near_bits - 1) {
                const size_t c = c0 + size_t(std::countr_zero(near_bits));
                const float p = cand[c];
                if (axis_best.axis == a && p == axis_best.pos) continue;  // same plane, same counts
                const size_t b = below[c], ab = above[c], fl = planar[c];
                const double l = exact_cost(p, b + fl, ab);
                const double r = fl > 0 ? exact_cost(p, b, ab + fl) : pos_inf;
                const bool planar_left = l <= r;
                const double cost = planar_left ? l : r;
                if (cost < axis_best.cost || (cost == axis_best.cost && p < axis_best.pos))
                    axis_best = {a,
                                 p,
                                 planar_left,
                                 cost,
                                 b + (planar_left ? fl : 0),
                                 ab + (planar_left ? 0 : fl)};
            }
        best = better(best, axis_best);
    }
    return best;
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
