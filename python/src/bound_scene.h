// The objects behind rtt.Scene and rtt.Tracer: a scene with its kd-tree built once on first
// need (under a lock, so Python threads may share the scene), and tracers over it.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "rtt/kdtree.h"
#include "rtt/render.h"
#include "rtt/scene.h"
#include "rtt/tracer.h"

namespace rtt::python {

class BoundScene {
public:
    /// `geometry_only`: loaded like `rtt render --mesh` (the file's materials, no lights, no
    /// camera), so renders of it match the command line's.
    BoundScene(Scene scene, bool geometry_only);

    const Scene& scene() const { return scene_; }
    bool geometry_only() const { return geometry_only_; }
    /// The kd-tree, built on the first call (thread-safe).
    const KdTree& tree();
    /// The camera a render uses when none is given: the scene's, else a diagonal view.
    Camera default_camera() const;

    /// rtt.render's "auto" (rtt::auto_rays_per_triangle): the tracer of the next frame, "bvh"
    /// until the frames it rendered were given that many rays per triangle or the kd-tree was
    /// built for another tracer, then "rtt"; each made once and kept while in use (thread-safe).
    std::shared_ptr<const Tracer> auto_tracer();
    /// Counts the rays a frame from auto_tracer() was given.
    void auto_rendered(uint64_t rays);
    /// The kind auto_tracer() gives next: "bvh" or "rtt".
    std::string auto_kind();

private:
    bool auto_wants_rtt() const;  // under auto_mutex_

    Scene scene_;
    bool geometry_only_;
    std::once_flag tree_once_;
    std::unique_ptr<KdTree> tree_;
    std::atomic<bool> tree_built_{false};
    std::mutex auto_mutex_;
    std::shared_ptr<const Tracer> auto_tracer_;
    bool auto_rtt_ = false;  ///< auto_tracer_ is the rtt kind's
    uint64_t auto_rays_ = 0;
};

/// Statistics of the last call on a tracer (any thread's); `rtt` stays zero for arbitrary rays
/// and for tracers other than RTT's.
using CallStats = KindStats;

class BoundTracer {
public:
    BoundTracer(std::shared_ptr<BoundScene> scene, const std::string& kind);

    const std::string& kind() const { return kind_; }
    const Tracer& tracer() const { return *tracer_; }
    const std::shared_ptr<BoundScene>& scene() const { return scene_; }

    /// Arbitrary rays: closest hits, `threads` = 0 for all cores.
    void intersect(std::span<const Ray> rays, std::span<Hit> hits, int threads);
    void visible(std::span<const Ray> rays, std::span<uint8_t> visible, int threads);
    /// Every primary sample of a width x height image with aa x aa samples, traced as the
    /// renderer traces it (shaft regions of 4x4-pixel tiles); hits (and, if not empty, how each
    /// sample was answered) in row-major (H*aa) x (W*aa) order.
    void camera_hits(const Camera& camera, int width, int height, int aa, std::span<Hit> hits,
                     std::span<SampleAnswer> answers, int threads);

    CallStats last_stats() const;

private:
    void record(const CallStats& stats);

    std::shared_ptr<BoundScene> scene_;
    std::string kind_;
    std::unique_ptr<Tracer> tracer_;
    mutable std::mutex stats_mutex_;
    CallStats last_;
};

/// What `rtt render` does with a scene, camera and lights, as one call: the lights given
/// replace the scene's (`make_point_light`), a scene without lights is lit from the eye.
RenderResult render_like_cli(const BoundScene& scene, const Tracer& tracer,
                             const std::optional<Camera>& camera,
                             const std::optional<std::vector<Vec3f>>& lights,
                             RenderOptions options);

}  // namespace rtt::python
