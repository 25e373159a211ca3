// Regions larger than a cell (RayTile::cell, RenderOptions::region): one shaft for the whole
// region first, then, where it gives no list, its halves along each side down to single cells
// (quadrants of a square region), and only then rays traced. At K = 1 a 4x4-pixel cell is one
// 16-wide packet, so a shaft pays only when it answers many cells at once (docs/benchmarks.md,
// "RTT against Embree"). Every part is an ordinary shaft tile of its own corners, so the
// exactness argument of a tile holds for it unchanged (docs/design.md, "Regions").
#include <algorithm>
#include <vector>

#include "trace/rtt_tracer.h"

namespace rtt::rtt_detail {

namespace {

/// Per-thread copies of a part's samples (a part is not contiguous in its region). A part's
/// copy is dead once its shaft has answered or declined, so its halves reuse the same buffers.
struct PartScratch {
    std::vector<Ray> rays;
    std::vector<Hit> hits;
    std::vector<Vec3f> points;
    std::vector<uint32_t> triangles;
    std::vector<uint8_t> active, visible;
    std::vector<SampleAnswer> answers;
};
thread_local PartScratch tls_part;

/// Copies rows [p.y, p.y + p.h) x columns [p.x, p.x + p.w) of a width-wide grid into `out`.
template <typename T>
void gather(std::span<const T> grid, int width, int x, int y, int w, int h, std::vector<T>& out) {
    out.resize(size_t(w) * size_t(h));
    for (int r = 0; r < h; ++r)
        std::copy_n(grid.begin() + (size_t(y + r) * size_t(width) + size_t(x)), w,
                    out.begin() + size_t(r) * size_t(w));
}

template <typename T>
void scatter(const std::vector<T>& in, int width, int x, int y, int w, int h, std::span<T> grid) {
    for (int r = 0; r < h; ++r)
        std::copy_n(in.begin() + size_t(r) * size_t(w), w,
                    grid.begin() + (size_t(y + r) * size_t(width) + size_t(x)));
}

/// Calls fn(part) for the halves of `p` along each side of more than one cell.
template <typename Fn>
void for_each_half(int x, int y, int w, int h, int cell, Fn&& fn) {
    const int wx = w > cell ? (w / cell / 2) * cell : w, wy = h > cell ? (h / cell / 2) * cell : h;
    for (int j = 0; j < (wy < h ? 2 : 1); ++j)
        for (int i = 0; i < (wx < w ? 2 : 1); ++i)
            fn(x + i * wx, y + j * wy, i ? w - wx : wx, j ? h - wy : wy);
}

}  // namespace

void RttTracer::intersect_region(const RayTile& tile, Part p, std::span<Hit> hits,
                                 std::span<SampleAnswer> answers, TraceStats& st) const {
    const bool whole = p.w == tile.width && p.h == tile.height;
    const bool cell = p.w <= tile.cell && p.h <= tile.cell;
    if (!shaft_tile(true, p.w, p.h, size_t(p.w) * size_t(p.h))) {
        // too large for one shaft (rtt_max_tile_samples): its parts are tried
    } else if (whole) {
        if (intersect_shaft(tile, hits, answers, st, !cell)) return;
    } else {
        PartScratch& s = tls_part;
        gather(tile.rays, tile.width, p.x, p.y, p.w, p.h, s.rays);
        s.hits.resize(s.rays.size());
        const bool map = !answers.empty();
        if (map) s.answers.assign(s.rays.size(), SampleAnswer::traced);
        const RayTile sub{p.w, p.h, s.rays, true, tile.cell};
        if (intersect_shaft(sub, s.hits, map ? std::span(s.answers) : std::span<SampleAnswer>(),
                            st, !cell)) {
            scatter(s.hits, tile.width, p.x, p.y, p.w, p.h, hits);
            if (map) scatter(s.answers, tile.width, p.x, p.y, p.w, p.h, answers);
            return;
        }
    }
    for_each_half(p.x, p.y, p.w, p.h, tile.cell, [&](int x, int y, int w, int h) {
        intersect_region(tile, Part{x, y, w, h}, hits, answers, st);
    });
}

void RttTracer::occluded_region(const SegmentTile& tile, Part p, std::span<uint8_t> visible,
                                std::span<SampleAnswer> answers, TraceStats& st) const {
    const bool whole = p.w == tile.width && p.h == tile.height;
    const bool cell = p.w <= tile.cell && p.h <= tile.cell;
    if (!shaft_tile(true, p.w, p.h, size_t(p.w) * size_t(p.h))) {
        // too large for one shaft (rtt_max_tile_samples): its parts are tried
    } else if (whole) {
        if (occluded_shaft(tile, visible, answers, st, !cell)) return;
    } else {
        PartScratch& s = tls_part;
        gather(tile.active, tile.width, p.x, p.y, p.w, p.h, s.active);
        if (std::all_of(s.active.begin(), s.active.end(), [](uint8_t a) { return a == 0; }))
            return;  // no segment asked for: visible stays 0
        gather(tile.points, tile.width, p.x, p.y, p.w, p.h, s.points);
        gather(tile.triangles, tile.width, p.x, p.y, p.w, p.h, s.triangles);
        s.visible.assign(s.active.size(), 0);
        const bool map = !answers.empty();
        if (map) s.answers.assign(s.active.size(), SampleAnswer::traced);
        const SegmentTile sub{p.w, p.h, tile.light, s.points, s.triangles, s.active, true,
                              tile.cell};
        if (occluded_shaft(sub, s.visible, map ? std::span(s.answers) : std::span<SampleAnswer>(),
                           st, !cell)) {
            scatter(s.visible, tile.width, p.x, p.y, p.w, p.h, visible);
            if (map) scatter(s.answers, tile.width, p.x, p.y, p.w, p.h, answers);
            return;
        }
    }
    for_each_half(p.x, p.y, p.w, p.h, tile.cell, [&](int x, int y, int w, int h) {
        occluded_region(tile, Part{x, y, w, h}, visible, answers, st);
    });
}

}  // namespace rtt::rtt_detail
