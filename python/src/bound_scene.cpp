#include "bound_scene.h"

#include <tbb/blocked_range2d.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>

#include "arrays.h"
#include "rtt/camera.h"
#include "rtt/error.h"

namespace rtt::python {
namespace {

/// Runs f in an arena of `threads` threads (0 = all cores) and returns its wall seconds.
template <typename F>
double timed_in_arena(int threads, const F& f) {
    const auto start = std::chrono::steady_clock::now();
    in_arena(threads, f);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// What tracers that never read a kd-tree are handed (rtt::tracer_uses_kdtree).
const KdTree& no_kdtree() {
    static const KdTree empty;
    return empty;
}

}  // namespace

BoundScene::BoundScene(Scene scene, bool geometry_only)
    : scene_(std::move(scene)), geometry_only_(geometry_only) {
    validate(scene_);
}

const KdTree& BoundScene::tree() {
    std::call_once(tree_once_, [&] {
        tree_ = std::make_unique<KdTree>(build_kdtree(scene_));
        tree_built_ = true;
    });
    return *tree_;
}

bool BoundScene::auto_wants_rtt() const {
    return tree_built_ || auto_paid_for_rtt(auto_rays_, scene_.triangle_count());
}

std::shared_ptr<const Tracer> BoundScene::auto_tracer() {
    std::lock_guard lock(auto_mutex_);
    if (!auto_tracer_ || (!auto_rtt_ && auto_wants_rtt())) {
        // Renders still holding the bvh tracer keep it until they finish.
        auto_rtt_ = auto_wants_rtt();
        auto_tracer_ = auto_rtt_ ? make_tracer("rtt", scene_, tree())
                                 : make_tracer("bvh", scene_, no_kdtree());
    }
    return auto_tracer_;
}

void BoundScene::auto_rendered(uint64_t rays) {
    std::lock_guard lock(auto_mutex_);
    auto_rays_ += rays;
}

std::string BoundScene::auto_kind() {
    std::lock_guard lock(auto_mutex_);
    return auto_rtt_ || auto_wants_rtt() ? "rtt" : "bvh";
}

Camera BoundScene::default_camera() const {
    if (scene_.camera && !geometry_only_) return *scene_.camera;
    return default_camera_for(scene_.bounds());
}

BoundTracer::BoundTracer(std::shared_ptr<BoundScene> scene, const std::string& kind)
    : scene_(std::move(scene)),
      kind_(kind),
      tracer_(make_tracer(kind, scene_->scene(),
                          tracer_uses_kdtree(kind) ? scene_->tree() : no_kdtree())) {}

void BoundTracer::record(const CallStats& stats) {
    std::lock_guard lock(stats_mutex_);
    last_ = stats;
}

CallStats BoundTracer::last_stats() const {
    std::lock_guard lock(stats_mutex_);
    return last_;
}

void BoundTracer::intersect(std::span<const Ray> rays, std::span<Hit> hits, int threads) {
    CallStats stats;
    stats.seconds =
        timed_in_arena(threads, [&] { intersect_rays(*tracer_, rays, hits, &stats.trace); });
    record(stats);
}

void BoundTracer::visible(std::span<const Ray> rays, std::span<uint8_t> out, int threads) {
    CallStats stats;
    stats.seconds =
        timed_in_arena(threads, [&] { visible_rays(*tracer_, rays, out, &stats.trace); });
    record(stats);
}

void BoundTracer::camera_hits(const Camera& camera, int width, int height, int aa,
                              std::span<Hit> hits, std::span<SampleAnswer> answers, int threads) {
    RenderOptions limits;
    limits.width = width;
    limits.height = height;
    limits.aa = aa;
    limits.validate(0);
    const CameraRays rays(camera, width, height, aa);
    // The renderer's regions (RenderOptions::region's default), so RTT answers as it does there.
    const int r = limits.region_pixels() / 4, cell = r > 1 ? 4 * aa : 0;
    const size_t row = size_t(width) * size_t(aa);
    const int tiles_x = (width + 3) / 4, tiles_y = (height + 3) / 4;
    const int regions_x = (tiles_x + r - 1) / r, regions_y = (tiles_y + r - 1) / r;
    tbb::combinable<CallStats> partial;
    const double s = timed_in_arena(threads, [&] {
        tbb::parallel_for(
            tbb::blocked_range2d<int>(0, regions_y, 0, regions_x), [&](const auto& range) {
                std::vector<Ray> tile;
                std::vector<Hit> tile_hits;
                std::vector<SampleAnswer> tile_answers;
                for (int ry = range.rows().begin(); ry != range.rows().end(); ++ry)
                    for (int rx = range.cols().begin(); rx != range.cols().end(); ++rx) {
                        const int tx = rx * r, ty = ry * r;
                        const int cols = std::min(r, tiles_x - tx),
                                  rows = std::min(r, tiles_y - ty);
                        const int w = 4 * aa * cols, h = 4 * aa * rows;
                        tile.resize(size_t(w) * size_t(h));
                        tile_hits.resize(tile.size());
                        tile_answers.resize(answers.empty() ? 0 : tile.size());
                        rays.region_rays(tx, ty, cols, rows, tile);
                        tracer_->intersect(RayTile{w, h, tile, true, cell}, tile_hits,
                                           partial.local().context(tile_answers));
                        // Sample (sc, sr) of the region is grid sample (4 tx K + sc, 4 ty K + sr);
                        // padding beyond the image is dropped.
                        for (int sr = 0; sr < h; ++sr) {
                            const int gy = 4 * ty * aa + sr;
                            if (gy >= height * aa) break;
                            for (int sc = 0; sc < w; ++sc) {
                                const int gx = 4 * tx * aa + sc;
                                if (gx >= width * aa) break;
                                const size_t at = size_t(gy) * row + size_t(gx),
                                             in = size_t(sr * w + sc);
                                hits[at] = tile_hits[in];
                                if (!answers.empty()) answers[at] = tile_answers[in];
                            }
                        }
                    }
            });
    });
    CallStats total;
    partial.combine_each([&](const CallStats& t) { total += t; });
    total.seconds = s;
    record(total);
}

RenderResult render_like_cli(const BoundScene& bound, const Tracer& tracer,
                             const std::optional<Camera>& camera,
                             const std::optional<std::vector<Vec3f>>& lights,
                             RenderOptions options) {
    Scene scene = bound.scene();  // lights change per call; geometry is the tracer's
    const Bbox3f bounds = scene.bounds();
    options.camera = camera ? *camera : bound.default_camera();
    if (lights && !lights->empty()) {
        if (lights->size() > max_lights)
            throw Error(std::to_string(lights->size()) + " lights given; at most " +
                        std::to_string(max_lights) + " are supported");
        scene.lights.clear();
        for (const Vec3f& p : *lights)
            scene.lights.push_back(make_point_light(p, bounds, lights->size()));
    } else if (scene.lights.empty()) {
        scene.lights.push_back(make_point_light(options.camera.position, bounds, 1));
    }
    options.validate(scene.lights.size());
    return render(scene, tracer, options);
}

}  // namespace rtt::python
