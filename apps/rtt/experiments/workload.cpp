#include "experiments/workload.h"

#include <algorithm>
#include <filesystem>
#include <string>

#include "core/platform.h"
#include "render/render_internal.h"
#include "rtt/builtin_scenes.h"
#include "rtt/camera.h"
#include "rtt/error.h"
#include "rtt/render.h"
#include "rtt/scene_io.h"

namespace rtt::bench {

void require_scene(const std::string& name_or_file) {
    std::error_code ec;
    if (is_builtin_scene(name_or_file) || std::filesystem::is_regular_file(name_or_file, ec))
        return;
    std::string names;
    for (const BuiltinSceneInfo& s : builtin_scenes())
        names += (names.empty() ? "" : ", ") + s.name;
    throw Error("unknown scene '" + name_or_file + "' (built-in scenes: " + names +
                "; or a scene file)");
}

BenchScene load_bench_scene(
    const std::string& name_or_file,
    const std::function<KdTree(const std::string& name, const Scene&)>& make_tree) {
    require_scene(name_or_file);
    BenchScene s;
    s.name = name_or_file;
    s.scene = is_builtin_scene(name_or_file) ? make_builtin_scene(name_or_file)
                                             : load_scene_file(name_or_file);
    validate(s.scene);
    s.camera = s.scene.camera ? *s.scene.camera : default_camera_for(s.scene.bounds());
    s.tree = make_tree ? make_tree(name_or_file, s.scene) : build_kdtree(s.scene);
    return s;
}

RayTile Band::ray_tile(size_t t) const {
    return RayTile{tile_width(t), tile_height(t),
                   std::span<const Ray>(rays).subspan(tile_offset(t), tile_size(t)), true, cell};
}

SegmentTile Band::segment_tile(const ShadowJob& job, const Vec3f& light_position) const {
    const size_t n = tile_size(job.tile), first = tile_offset(job.tile);
    return SegmentTile{tile_width(job.tile),
                       tile_height(job.tile),
                       light_position,
                       std::span<const Vec3f>(points).subspan(first, n),
                       std::span<const uint32_t>(triangles).subspan(first, n),
                       std::span<const uint8_t>(masks).subspan(job.mask_offset, n),
                       true,
                       cell};
}

std::vector<Hit> Band::intersect(const Tracer& tracer) const {
    std::vector<Hit> hits(rays.size());
    for (size_t t = 0; t < tile_count(); ++t)
        tracer.intersect(ray_tile(t), std::span(hits).subspan(tile_offset(t), tile_size(t)));
    return hits;
}

void Band::prefetch_ray_tile(size_t t) const {
    if (t >= tile_count()) return;
    prefetch_bytes(rays.data() + tile_offset(t), tile_size(t) * sizeof(Ray));
}

void Band::prefetch_shadow_job(size_t j) const {
    if (j >= shadow_jobs.size()) return;
    const ShadowJob& job = shadow_jobs[j];
    const size_t n = tile_size(job.tile), first = tile_offset(job.tile);
    prefetch_bytes(points.data() + first, n * sizeof(Vec3f));
    prefetch_bytes(triangles.data() + first, n * sizeof(uint32_t));
    prefetch_bytes(masks.data() + job.mask_offset, n);
}

/// The renderer's shading context, kept for its light constants, surface_at and can_light:
/// the benchmark's active segments are decided by the renderer's own code, not a copy of it.
/// make_context stores a tracer it never calls here; the reference tracer is cheap to make.
struct Workload::Lighting {
    RenderOptions options;
    std::unique_ptr<Tracer> tracer;
    render_detail::RenderContext context;

    explicit Lighting(const BenchScene& s)
        : tracer(make_tracer("ray", s.scene, s.tree)),
          context(render_detail::make_context(s.scene, *tracer, options)) {}
};

Workload::Workload(const BenchScene& scene, int width, int height, int aa, size_t band_samples,
                   int region)
    : scene_(&scene), width_(width), height_(height), aa_(aa) {
    RenderOptions check;
    check.width = width;
    check.height = height;
    check.aa = aa;
    check.region = region;
    check.validate(scene.scene.lights.size());
    region_ = check.region_pixels();
    tiles_x_ = (width + region_ - 1) / region_;
    tiles_y_ = (height + region_ - 1) / region_;
    const size_t row_samples =
        size_t(4 * ((width + 3) / 4)) * size_t(region_) * size_t(aa) * size_t(aa);
    const int rows_per_band =
        int(std::max<size_t>(1, (band_samples + row_samples - 1) / row_samples));
    for (int row = 0; row < tiles_y_; row += rows_per_band)
        band_rows_.emplace_back(row, std::min(rows_per_band, tiles_y_ - row));
    lighting_ = std::make_shared<const Lighting>(scene);
}

uint64_t Workload::primary_rays() const {
    return uint64_t(4 * ((width_ + 3) / 4)) * uint64_t(4 * ((height_ + 3) / 4)) * uint64_t(aa_) *
           uint64_t(aa_);
}

Band Workload::make_band(int b) const {
    const CameraRays camera(scene_->camera, width_, height_, aa_);
    const int n = region_ * aa_, r = region_ / 4;
    Band band;
    band.first_tile_row = band_rows_[size_t(b)].first;
    band.tile_rows = band_rows_[size_t(b)].second;
    band.tiles_x = tiles_x_;
    band.side = n;
    band.pixels = region_;
    band.cell = r > 1 ? 4 * aa_ : 0;
    // Regions cut at the image padded to multiples of 4, as the renderer's.
    const int cols4 = (width_ + 3) / 4, rows4 = (height_ + 3) / 4;
    const int last_cols = cols4 - (tiles_x_ - 1) * r, last_rows = rows4 - (tiles_y_ - 1) * r;
    band.last_width = 4 * aa_ * last_cols;
    const bool last_band = band.first_tile_row + band.tile_rows == tiles_y_;
    band.last_height = last_band ? 4 * aa_ * last_rows : n;
    band.rays.resize(band.tile_offset(band.tile_count() - 1) +
                     band.tile_size(band.tile_count() - 1));
    // The renderer's rays (CameraRays::region_rays); tests/bench_test.cpp also checks the hits
    // against render()'s hit buffer.
    size_t t = 0;
    for (int ty = band.first_tile_row; ty < band.first_tile_row + band.tile_rows; ++ty)
        for (int tx = 0; tx < tiles_x_; ++tx, ++t)
            camera.region_rays(
                tx * r, ty * r, tx + 1 == tiles_x_ ? last_cols : r,
                ty + 1 == tiles_y_ ? last_rows : r,
                std::span(band.rays).subspan(band.tile_offset(t), band.tile_size(t)));
    return band;
}

void Workload::add_shadows(Band& band, std::span<const Hit> hits) const {
    const render_detail::RenderContext& ctx = lighting_->context;
    band.points.resize(band.rays.size());
    band.triangles.resize(band.rays.size());
    band.masks.clear();
    band.shadow_jobs.clear();
    std::vector<render_detail::SurfacePoint> surf(band.tile_samples());
    std::vector<uint8_t> mask(band.tile_samples());
    for (size_t t = 0; t < band.tile_count(); ++t) {
        const size_t n = band.tile_size(t), first = band.tile_offset(t);
        // As render_detail::trace_shadows: a miss keeps the ray origin as a filler point.
        for (size_t i = 0; i < n; ++i) {
            const size_t s = first + i;
            if (hits[s].valid()) surf[i] = render_detail::surface_at(ctx, band.rays[s], hits[s]);
            band.points[s] = hits[s].valid() ? surf[i].p : band.rays[s].org;
            band.triangles[s] = hits[s].tri;
        }
        for (size_t l = 0; l < ctx.lights.size(); ++l) {
            uint32_t active = 0;
            for (size_t i = 0; i < n; ++i) {
                mask[i] =
                    hits[first + i].valid() && render_detail::can_light(ctx.lights[l], surf[i]);
                active += mask[i];
            }
            if (active == 0) continue;  // the renderer does not trace this light for this tile
            band.shadow_jobs.push_back(
                ShadowJob{uint32_t(t), uint32_t(l), active, band.masks.size()});
            band.masks.insert(band.masks.end(), mask.begin(), mask.begin() + long(n));
        }
    }
}

}  // namespace rtt::bench
