// The rays of a benchmark: exactly the batches the renderer hands to its tracer (render.h,
// "Batches handed to the tracer"), generated once and handed unchanged to every tracer.
//
// Primary: one RayTile per region of R x R pixels (RenderOptions::region, default
// default_region(K)), RK x RK rays, shaft = true, cell = 4K (0 when R = 4), over the image
// padded to multiples of 4: regions at the right and bottom edges are cut there, as the
// renderer cuts them. Shadow: per tile and light, one SegmentTile whose points are the hit points
// of the BASELINE tracer's primary hits (so every tracer answers the very same segments), whose
// active mask follows the renderer's rule (render_detail::can_light: omni lights on the side of
// the hit triangle the ray came from, spots also strictly inside the outer cone), and which is
// skipped, like in the renderer, when no segment of the tile is active for that light.
// Reflected rays are not part of the benchmark (the paper's Table 1 times primary and shadow).
//
// A frame is cut into bands of whole tile rows so that memory stays bounded at any size
// (2048x1536 with 6x6 antialiasing is 113 M rays): the harness generates one band, runs every
// tracer on it, and moves on.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "rtt/kdtree.h"
#include "rtt/scene.h"
#include "rtt/tracer.h"

namespace rtt::bench {

/// A scene ready to trace: geometry, kd-tree and the camera the renderer would use.
struct BenchScene {
    std::string name;
    Scene scene;
    KdTree tree;
    Camera camera;  ///< The scene's own, else default_camera_for(bounds) as `rtt render` does.
};

/// Throws rtt::Error unless `name_or_file` is a built-in scene's name or an existing file (so
/// that a long benchmark run fails before it starts, not after an hour).
void require_scene(const std::string& name_or_file);

/// Loads a built-in scene by name, or a scene file (JSON or any mesh format), and builds its
/// kd-tree on the calling thread's oneTBB arena. Throws rtt::Error for an unknown name or a
/// bad file. `make_tree`, if given, makes the tree instead (`rtt bench --load-tree`).
BenchScene load_bench_scene(
    const std::string& name_or_file,
    const std::function<KdTree(const std::string& name, const Scene&)>& make_tree = {});

/// The shadow segments of one tile towards one light (a SegmentTile over band-owned arrays).
struct ShadowJob {
    uint32_t tile = 0;       ///< Tile index inside the band.
    uint32_t light = 0;      ///< Scene light index.
    uint32_t active = 0;     ///< Active segments (the rays this job asks for).
    size_t mask_offset = 0;  ///< Start of its active mask in Band::masks (n * n bytes).
};

/// Consecutive whole tile rows of a frame, with the rays every tracer gets.
struct Band {
    int first_tile_row = 0;
    int tile_rows = 0;
    int tiles_x = 0;
    int side = 0;           ///< Samples per tile side, RK (tiles at the image's edge: fewer).
    int pixels = 4;         ///< Pixels per tile side, R.
    int cell = 0;           ///< RayTile::cell, 4K (0 when a tile is one cell).
    int last_width = 0;     ///< Samples per row of the tiles of the last column.
    int last_height = 0;    ///< Sample rows of the tiles of the last row.
    std::vector<Ray> rays;  ///< Tile after tile (row-major tiles), row-major samples in each.

    // Filled by Workload::add_shadows from the baseline's primary hits.
    std::vector<Vec3f> points;        ///< Hit point per sample (ray origin for a miss).
    std::vector<uint32_t> triangles;  ///< Hit triangle per sample.
    std::vector<uint8_t> masks;       ///< Active masks of the shadow jobs, back to back.
    std::vector<ShadowJob> shadow_jobs;

    size_t tile_count() const { return size_t(tile_rows) * size_t(tiles_x); }
    /// Samples of the largest tile (scratch buffers).
    size_t tile_samples() const { return size_t(side) * size_t(side); }
    int tile_width(size_t t) const {
        return t % size_t(tiles_x) + 1 == size_t(tiles_x) ? last_width : side;
    }
    int tile_height(size_t t) const {
        return t / size_t(tiles_x) + 1 == size_t(tile_rows) ? last_height : side;
    }
    size_t tile_size(size_t t) const { return size_t(tile_width(t)) * size_t(tile_height(t)); }
    /// First sample of tile t in `rays` (and in every per-sample array of the band).
    size_t tile_offset(size_t t) const {
        const size_t row = t / size_t(tiles_x), col = t % size_t(tiles_x);
        return row * size_t(side) * size_t(row_width()) +
               col * size_t(side) * size_t(tile_height(t));
    }
    /// Samples per row of tiles (all columns).
    int row_width() const { return (tiles_x - 1) * side + last_width; }
    /// Primary tile t of this band.
    RayTile ray_tile(size_t t) const;
    /// Every primary ray of the band traced by `tracer`, tile after tile, on this thread.
    std::vector<Hit> intersect(const Tracer& tracer) const;
    /// Shadow tile of job j towards `light_position` (the scene's light of that job).
    SegmentTile segment_tile(const ShadowJob& job, const Vec3f& light_position) const;
    /// Start loading the inputs of primary tile t / shadow job j into the cache. The harness
    /// calls it one tile ahead, so that tracers read their tile as the renderer's do: it
    /// generates a tile's rays, and its shadow points from that tile's hits, right before
    /// tracing them. Without it every tracer waits on memory for each tile's first rays (the
    /// bands are larger than L2), which added the same time per tile to every tracer.
    void prefetch_ray_tile(size_t t) const;
    void prefetch_shadow_job(size_t j) const;
};

/// One image configuration of one scene: W x H pixels, K x K samples per pixel.
class Workload {
public:
    /// `band_samples`: bands hold at least this many samples (whole tile rows; the last band
    /// may be smaller). `region`: pixels per tile side as RenderOptions::region (0 = the
    /// default). Throws rtt::Error for a size, K or region out of the renderer's range.
    Workload(const BenchScene& scene, int width, int height, int aa, size_t band_samples,
             int region = 0);

    const BenchScene& scene() const { return *scene_; }
    int width() const { return width_; }
    int height() const { return height_; }
    int aa() const { return aa_; }
    int region() const { return region_; }
    int tiles_x() const { return tiles_x_; }
    int tiles_y() const { return tiles_y_; }
    int band_count() const { return int(band_rows_.size()); }
    /// Primary rays of the whole frame (padded to whole tiles: what the tracers are asked).
    uint64_t primary_rays() const;

    /// The primary rays of band b, exactly as the renderer generates them (CONVENTIONS'
    /// formula for pixel (R tx + sc / K, R ty + sr / K), sample (sc % K, sr % K)).
    Band make_band(int b) const;

    /// Fills the band's shadow jobs from the primary hits (one per band sample, band order),
    /// with the renderer's active rule.
    void add_shadows(Band& band, std::span<const Hit> hits) const;

private:
    const BenchScene* scene_;
    int width_, height_, aa_, region_;
    int tiles_x_, tiles_y_;
    std::vector<std::pair<int, int>> band_rows_;  ///< (first tile row, rows) per band.
    struct Lighting;
    std::shared_ptr<const Lighting> lighting_;
};

}  // namespace rtt::bench
