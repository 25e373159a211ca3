// Arbitrary rays grouped by direction octant and origin cell (ray_order.h): one counting sort.
#include "trace/ray_order.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <cfloat>
#include <cstdint>

namespace rtt {
namespace {

/// Bits per axis of the origins' cells, at most.
constexpr int max_cell_bits = 7;

/// The bits of a cell index spread to every third bit (the Morton code's interleave).
struct Spread3 {
    uint32_t of[1u << max_cell_bits];
    constexpr Spread3() : of() {
        for (uint32_t v = 0; v < (1u << max_cell_bits); ++v)
            for (int b = 0; b < max_cell_bits; ++b) of[v] |= ((v >> b) & 1u) << (3 * b);
    }
};
constexpr Spread3 spread3;

Bbox3f origin_bounds(std::span<const Ray> rays) {
    return tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, rays.size(), 4096), Bbox3f{},
        [&](const tbb::blocked_range<size_t>& r, Bbox3f box) {
            for (size_t i = r.begin(); i != r.end(); ++i) box.extend(rays[i].org);
            return box;
        },
        [](Bbox3f a, const Bbox3f& b) {
            a.extend(b);
            return a;
        });
}

}  // namespace

large_vector<uint32_t> coherent_order(std::span<const Ray> rays) {
    const size_t n = rays.size();
    // Positions are 32-bit: a larger batch (128 GB of rays) is traced as it comes.
    if (n < reorder_min_rays || n > UINT32_MAX) return {};
    // Cells per axis: 2^bits, with 8 octants about n / 4 buckets (measured: 5 to 8 bits per
    // axis for 1M rays trace alike, 3 slower; docs/benchmarks.md).
    const int bits = std::clamp(int(std::bit_width(n / 32)) / 3, 1, max_cell_bits);
    const Bbox3f box = origin_bounds(rays);
    const Vec3f lo = box.lo;
    const float cells_per_axis = float(1u << bits);
    const Vec3f extent = box.hi - box.lo;
    // An axis without extent (or beyond float) has one cell: its scale 0, its cell below.
    const auto scale_of = [&](float e) {
        return e > 0.f && e <= FLT_MAX ? cells_per_axis / e : 0.f;
    };
    const Vec3f scale{scale_of(extent.x), scale_of(extent.y), scale_of(extent.z)};
    const uint32_t cells = 1u << (3 * bits), top = (1u << bits) - 1u;
    // A NaN position (an infinite offset times a zero scale) lands in the top cell.
    const auto cell = [top](float position) {
        return position < float(top) ? uint32_t(position) : top;
    };
    const auto morton_of = [&](const Vec3f& org) {
        const Vec3f at = (org - lo) * scale;
        return spread3.of[cell(at.x)] << 2 | spread3.of[cell(at.y)] << 1 | spread3.of[cell(at.z)];
    };
    // Rays that already follow their origins (a frame's bounces in pixel order, a camera's rays)
    // are traced as they come: grouping them saved nothing and the gathering cost 5-10 %
    // (docs/benchmarks.md). Judged on pairs of neighbours spread over the batch.
    constexpr size_t samples = 1024;
    size_t same_cell = 0;
    for (size_t k = 0; k < samples; ++k) {
        const size_t i = k * (n - 1) / samples;
        same_cell += morton_of(rays[i].org) == morton_of(rays[i + 1].org);
    }
    if (same_cell * 2 >= samples) return {};
    // The order in [0, n) and the keys in [n, 2n) of one array: from 512k rays on it takes huge
    // pages, where fresh 4 KiB pages faulted for longer than the sort took.
    large_vector<uint32_t> order(2 * n);
    const std::span<uint32_t> keys(order.data() + n, n);
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
            for (size_t i = r.begin(); i != r.end(); ++i) {
                const Ray& ray = rays[i];
                const uint32_t octant = uint32_t(ray.dir.x < 0.f) | uint32_t(ray.dir.y < 0.f) << 1 |
                                        uint32_t(ray.dir.z < 0.f) << 2;
                keys[i] = octant * cells + morton_of(ray.org);
            }
        });
    // A stable counting sort over consecutive parts of the batch, one per thread: each part's
    // counts, then each bucket's first slot per part (buckets in key order, parts in batch
    // order), then each part's rays to its slots. Stable, so the order is the same for any
    // number of parts. At least 65,536 rays a part, and no more counters than rays.
    const size_t buckets = size_t(8) * cells;
    const size_t parts = std::clamp<size_t>(size_t(tbb::this_task_arena::max_concurrency()), 1,
                                            std::max<size_t>(1, std::min(n / 65536, n / buckets)));
    const auto part_begin = [&](size_t p) { return p * n / parts; };
    large_vector<uint32_t> next(parts * buckets, 0);
    tbb::parallel_for(size_t(0), parts, [&](size_t p) {
        uint32_t* count = next.data() + p * buckets;
        for (size_t i = part_begin(p); i < part_begin(p + 1); ++i) ++count[keys[i]];
    });
    uint32_t at = 0;
    for (size_t b = 0; b < buckets; ++b)
        for (size_t p = 0; p < parts; ++p) {
            uint32_t& slot = next[p * buckets + b];
            const uint32_t count = slot;
            slot = at;
            at += count;
        }
    tbb::parallel_for(size_t(0), parts, [&](size_t p) {
        uint32_t* slot = next.data() + p * buckets;
        for (size_t i = part_begin(p); i < part_begin(p + 1); ++i)
            order[slot[keys[i]]++] = uint32_t(i);
    });
    order.resize(n);
    return order;
}

}  // namespace rtt
