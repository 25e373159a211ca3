// The image as regions of 4x4-pixel tiles (RTT's unit), rendered in parallel with oneTBB.
//
// A W x H image is padded up to multiples of 4; padding pixels get CONVENTIONS' rays for the
// ORIGINAL W, H (pixel x >= W simply continues the formula) and are cropped when samples are
// written out, so every tile the tracer sees is whole. Each region is independent and written
// to disjoint pixels, so the result does not depend on the thread count, schedule or region
// size.
#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <string>

#include "render/progress.h"
#include "render/render_internal.h"
#include "rtt/camera.h"
#include "rtt/error.h"
#include "rtt/memory_budget.h"

namespace rtt {

void RenderOptions::validate(size_t light_count) const {
    const std::string side = std::to_string(max_image_side);
    if (width < 1 || height < 1 || width > max_image_side || height > max_image_side)
        throw Error("image size " + std::to_string(width) + "x" + std::to_string(height) +
                    " out of range (each side 1.." + side + ")");
    if (aa < 1 || aa > max_aa)
        throw Error("antialiasing " + std::to_string(aa) + " out of range (1.." +
                    std::to_string(max_aa) + ")");
    const uint64_t samples = uint64_t(width) * uint64_t(height) * uint64_t(aa) * uint64_t(aa);
    if (samples > max_render_samples)
        throw Error("image " + std::to_string(width) + "x" + std::to_string(height) + " with " +
                    std::to_string(aa) + "x" + std::to_string(aa) + " antialiasing has " +
                    std::to_string(samples) + " samples; at most " +
                    std::to_string(max_render_samples) + " are allowed");
    require_memory(render_memory_bytes(*this), "image " + std::to_string(width) + "x" +
                                                   std::to_string(height) + " with " +
                                                   std::to_string(aa) + "x" + std::to_string(aa) +
                                                   " antialiasing and the requested buffers");
    if (max_depth < 0 || max_depth > max_reflection_depth)
        throw Error("reflection depth " + std::to_string(max_depth) + " out of range (0.." +
                    std::to_string(max_reflection_depth) + ")");
    if (region < 0 || region > max_region || region % 4 != 0)
        throw Error("region " + std::to_string(region) +
                    " out of range (0 = default, or a multiple of 4 up to " +
                    std::to_string(max_region) + ")");
    if (threads < 0 || threads > max_render_threads)
        throw Error("thread count " + std::to_string(threads) + " out of range (1.." +
                    std::to_string(max_render_threads) + ")");
    if (light_count > max_lights)
        throw Error(std::to_string(light_count) + " lights; at most " + std::to_string(max_lights) +
                    " are supported");
    if (!shadows && shadow_buffer)
        throw Error("a shadow buffer needs shadow segments (shadows are off)");
}

void AnswerMaps::validate(const RenderOptions& options, size_t light_count) const {
    if (shadow_light >= 0 && size_t(shadow_light) >= light_count)
        throw Error("shadow map light " + std::to_string(shadow_light) +
                    " does not exist (the scene has " + std::to_string(light_count) + " lights)");
    if (!options.shadows && shadow_light >= 0)
        throw Error("a shadow map needs shadow segments (shadows are off)");
    // RenderOptions::validate checked the image and buffers; the maps add a byte per pixel each.
    if (primary || shadow_light >= 0)
        require_memory(render_memory_bytes(options, *this),
                       "image " + std::to_string(options.width) + "x" +
                           std::to_string(options.height) + " with its answer maps");
}

int default_region(int aa) {
    return aa == 1 ? 32 : aa <= 8 ? 8 : 4;
}

int RenderOptions::region_pixels() const {
    return region > 0 ? region : default_region(aa);
}

namespace render_detail {
namespace {

struct TileJob {
    const RenderContext& ctx;
    const CameraRays& camera;
    RenderResult& out;
    int first_row = 0;  ///< Image row of out's first row (a band of tile rows).
};

/// The region of cols x rows 4x4-pixel tiles from tile (tx, ty), traced as one batch.
void render_region(const TileJob& job, int tx, int ty, int cols, int rows, ThreadStats& ts) {
    const RenderOptions& opt = job.ctx.options;
    const int k = opt.aa, n = 4 * k * cols, spp = k * k;
    const int w = opt.width, h = opt.height;

    RayBatch batch{n, 4 * k * rows, true, std::vector<Ray>(size_t(n) * size_t(4 * k * rows)),
                   4 * k};
    job.camera.region_rays(tx, ty, cols, rows, batch.rays);

    PrimaryRecord record;
    std::vector<Vec3f> colors(batch.rays.size());
    trace_batch(job.ctx, ts, batch, 0, colors, &record);

    RenderResult& out = job.out;
    for (int py = 0; py < 4 * rows; ++py) {
        const int y = ty * 4 + py;
        if (y >= h) break;
        for (int px = 0; px < 4 * cols; ++px) {
            const int x = tx * 4 + px;
            if (x >= w) break;
            Vec3f sum{0.f};
            int answered = 0, shadow_sum = 0, shadow_count = 0;
            for (int j = 0; j < k; ++j) {
                for (int i = 0; i < k; ++i) {
                    const size_t s = size_t(py * k + j) * n + size_t(px * k + i);
                    const size_t dst = ((size_t(y - job.first_row) * w + x) * k + j) * k + i;
                    sum += colors[s];
                    if (opt.hits_buffer) out.hits[dst] = record.hits[s].tri;
                    if (opt.shadow_buffer) out.shadows[dst] = record.visible[s];
                    if (job.ctx.maps.primary)
                        answered += record.primary_answers[s] != SampleAnswer::traced;
                    if (!record.shadow_active.empty() && record.shadow_active[s]) {
                        const SampleAnswer a = record.shadow_answers[s];
                        shadow_sum += a == SampleAnswer::answered_empty  ? 255
                                      : a == SampleAnswer::answered_list ? 128
                                                                         : 0;
                        ++shadow_count;
                    }
                }
            }
            const size_t pixel = size_t(y - job.first_row) * w + x;
            out.pixels[pixel] = sum / float(spp);
            if (opt.pixel_hits) {
                const Hit& first = record.hits[size_t(py * k) * n + size_t(px * k)];
                out.depth[pixel] = first.valid() ? first.t : pos_inf;
                out.first_triangle[pixel] = first.tri;
            }
            if (job.ctx.maps.primary)
                out.primary_map[pixel] = uint8_t((answered * 255 + spp / 2) / spp);
            if (job.ctx.maps.shadow_light >= 0)
                out.shadow_map[pixel] =
                    shadow_count ? uint8_t((shadow_sum + shadow_count / 2) / shadow_count) : 0;
        }
    }
}

}  // namespace
}  // namespace render_detail

namespace render_detail {
namespace {

/// Allocates `out` for pixel rows [first_row, first_row + rows) of the image.
void allocate(RenderResult& out, const RenderOptions& options, const AnswerMaps& maps,
              int first_row, int rows) {
    out.width = options.width;
    out.height = options.height;
    out.aa = options.aa;
    out.first_row = first_row;
    out.rows = rows;
    const size_t pixels = size_t(options.width) * size_t(rows);
    const size_t samples = pixels * size_t(options.aa) * size_t(options.aa);
    out.pixels.assign(pixels, Vec3f{0.f});
    if (options.hits_buffer) out.hits.assign(samples, 0);
    if (options.shadow_buffer) out.shadows.assign(samples, 0);
    if (maps.primary) out.primary_map.assign(pixels, 0);
    if (maps.shadow_light >= 0) out.shadow_map.assign(pixels, 0);
    if (options.pixel_hits) {
        out.depth.assign(pixels, 0.f);
        out.first_triangle.assign(pixels, 0);
    }
}

}  // namespace
}  // namespace render_detail

RenderStats render_bands(const Scene& scene, const Tracer& tracer, const RenderOptions& options,
                         const std::function<bool(int&, int&)>& next_band,
                         const std::function<void(RenderResult&)>& band_done,
                         const AnswerMaps& maps) {
    using namespace render_detail;
    const auto start = std::chrono::steady_clock::now();
    options.validate(scene.lights.size());
    maps.validate(options, scene.lights.size());
    const CameraRays camera(options.camera, options.width, options.height, options.aa);
    const RenderContext ctx = make_context(scene, tracer, options, maps);
    const int tiles_x = (options.width + 3) / 4, tiles_y = (options.height + 3) / 4;
    const int region_tiles = options.region_pixels() / 4;
    const int regions_x = (tiles_x + region_tiles - 1) / region_tiles;
    const int threads = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
    tbb::enumerable_thread_specific<ThreadStats> per_thread([&] {
        ThreadStats s;
        s.rays_by_depth.assign(size_t(options.max_depth) + 1, 0);
        return s;
    });
    {
        ProgressBar progress(uint64_t(tiles_x) * uint64_t(tiles_y), options.progress);
        tbb::task_arena arena(threads);
        int first_tile_row = 0, tile_rows = 0;
        while (next_band(first_tile_row, tile_rows)) {
            if (first_tile_row < 0 || tile_rows < 1 || first_tile_row + tile_rows > tiles_y)
                throw Error("render: band of tile rows [" + std::to_string(first_tile_row) + ", " +
                            std::to_string(first_tile_row + tile_rows) + ") outside the image's " +
                            std::to_string(tiles_y));
            const int first_row = 4 * first_tile_row;
            const int rows = std::min(options.height, 4 * (first_tile_row + tile_rows)) - first_row;
            RenderResult band;
            allocate(band, options, maps, first_row, rows);
            const TileJob job{ctx, camera, band, first_row};
            // Regions on the image's grid of region_tiles x region_tiles tiles, cut by the
            // band and the image's edge (the answers do not depend on how tiles are grouped).
            const int end_row = first_tile_row + tile_rows;
            const int region_rows =
                (end_row - 1) / region_tiles - first_tile_row / region_tiles + 1;
            const int first_region_row = first_tile_row / region_tiles;
            arena.execute([&] {
                tbb::parallel_for(
                    tbb::blocked_range<int>(0, region_rows * regions_x),
                    [&](const tbb::blocked_range<int>& r) {
                        ThreadStats& ts = per_thread.local();
                        for (int i = r.begin(); i < r.end(); ++i) {
                            const int rx = i % regions_x, ry = first_region_row + i / regions_x;
                            const int tx = rx * region_tiles,
                                      cols = std::min(region_tiles, tiles_x - tx);
                            const int ty = std::max(ry * region_tiles, first_tile_row);
                            const int rows = std::min((ry + 1) * region_tiles, end_row) - ty;
                            render_region(job, tx, ty, cols, rows, ts);
                            progress.advance(uint64_t(cols) * uint64_t(rows));
                        }
                    });
            });
            band_done(band);
        }
    }

    RenderStats stats;
    stats.rays_by_depth.assign(size_t(options.max_depth) + 1, 0);
    for (const ThreadStats& ts : per_thread) {
        KindStats* kinds[3] = {&stats.primary, &stats.shadow, &stats.secondary};
        for (int k = 0; k < 3; ++k) {
            *kinds[k] += ts.kinds[k];
        }
        for (size_t d = 0; d < ts.rays_by_depth.size(); ++d)
            stats.rays_by_depth[d] += ts.rays_by_depth[d];
    }
    stats.threads = threads;
    stats.wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return stats;
}

RenderResult render(const Scene& scene, const Tracer& tracer, const RenderOptions& options,
                    const AnswerMaps& maps) {
    RenderResult out;
    bool given = false;
    const int tiles_y = (options.height + 3) / 4;
    const RenderStats stats = render_bands(
        scene, tracer, options,
        [&](int& first, int& count) {
            if (given) return false;
            first = 0, count = tiles_y, given = true;
            return true;
        },
        [&](RenderResult& band) { out = std::move(band); }, maps);
    out.stats = stats;
    return out;
}

}  // namespace rtt
