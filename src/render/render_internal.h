// Pieces of the renderer shared by its files (not public API). See include/rtt/render.h for
// the batches handed to the tracer and the reflected-ray representation.
#pragma once

#include <chrono>
#include <span>
#include <vector>

#include "geom/triangle.h"
#include "rtt/render.h"
#include "rtt/scene.h"
#include "rtt/tracer.h"

namespace rtt::render_detail {

enum RayKind { primary_kind = 0, shadow_kind = 1, secondary_kind = 2 };

/// Counters of one worker thread, summed after the render.
struct ThreadStats {
    KindStats kinds[3];
    std::vector<uint64_t> rays_by_depth;  ///< [0] primary, [d] reflection depth d.
};

/// Runs `call` (one tracer call) and adds its steady-clock duration to `kind`.
template <typename Call>
void timed(KindStats& kind, Call&& call) {
    const auto start = std::chrono::steady_clock::now();
    call();
    kind.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// A light with the constants shading needs.
struct LightInfo {
    const Light* light = nullptr;
    Vec3f axis;              ///< Spot: normalized direction.
    float cos_outer = -1.f;  ///< Spot: cosine of the outer half-angle (-1 for omni).
    float cos_inner = -1.f;
};

/// Read-only state shared by every tile of one render.
struct RenderContext {
    const Scene& scene;
    const Tracer& tracer;
    const RenderOptions& options;
    AnswerMaps maps;
    std::vector<LightInfo> lights;
    float reflect_epsilon = 0.f;  ///< tmin of packed reflected rays (scene-scaled).
};

RenderContext make_context(const Scene& scene, const Tracer& tracer, const RenderOptions& options,
                           const AnswerMaps& maps = {});

/// A batch handed to the tracer as one RayTile.
struct RayBatch {
    int width = 0;
    int height = 0;
    bool shaft = false;
    std::vector<Ray> rays;
    int cell = 0;  ///< RayTile::cell: 4K when the batch is a region of 4x4-pixel tiles.
};

/// Per-sample extras of a primary tile (tile order), for buffers and the Figure 5 maps.
struct PrimaryRecord {
    std::vector<Hit> hits;
    std::vector<uint32_t> visible;              ///< Shadow buffer: pure visibility bits.
    std::vector<SampleAnswer> primary_answers;  ///< Primary map: how each ray was answered.
    std::vector<SampleAnswer> shadow_answers;   ///< Shadow map: how each segment was answered.
    std::vector<uint8_t> shadow_active;         ///< Shadow map: segments actually asked for.
};

/// Where a ray met a surface.
struct SurfacePoint {
    Vec3f p;   ///< org + t * dir, as CONVENTIONS computes it.
    Vec3f ng;  ///< Unit geometric normal on the ray's side.
    Vec3f ns;  ///< Unit shading normal on the ray's side.
    const Material* material = nullptr;
};

/// The plane of a triangle, computed one way for all (mirror identity compares it with ==).
struct Plane {
    Vec3f n;  ///< normalize(cross(v1 - v0, v2 - v0))
    float d;  ///< dot(n, v0)
};
Plane triangle_plane(const TriangleVerts& tri);

// shade.cpp
SurfacePoint surface_at(const RenderContext& ctx, const Ray& ray, const Hit& hit);
/// True when the light can light the point: it is on the side of the triangle's plane the ray
/// came from, and for a spot strictly inside the outer cone.
bool can_light(const LightInfo& light, const SurfacePoint& s);
/// Local Phong colour (ambient + each light whose bit is set in `lit`).
Vec3f shade(const RenderContext& ctx, const SurfacePoint& s, const Vec3f& dir, uint32_t lit);

// shadows.cpp
/// Traces the shadow segments of a traced batch. `lit` receives, per sample, the lights that
/// can light it and are visible. With `record` and a shadow buffer requested, every hit sample
/// gets a segment to every light and record->visible the pure visibility bits.
void trace_shadows(const RenderContext& ctx, ThreadStats& ts, const RayBatch& batch,
                   std::span<const Hit> hits, std::span<const SurfacePoint> surf,
                   std::span<uint32_t> lit, PrimaryRecord* record);

// reflect.cpp
/// Traces the reflected rays of the mirror samples of a batch traced at `depth` and mixes
/// them into `colors` (colour = (1 - m) local + m reflected); at depth == max_depth nothing is
/// traced and mirrors reflect black.
void trace_reflections(const RenderContext& ctx, ThreadStats& ts, const RayBatch& batch,
                       std::span<const Hit> hits, std::span<const SurfacePoint> surf, int depth,
                       std::span<Vec3f> colors);

// trace_batch.cpp
/// Traces `batch` at reflection depth `depth` (0 = primary) and writes each sample's colour:
/// closest hits, shadow segments, local shading, reflections. `record` only for depth 0.
void trace_batch(const RenderContext& ctx, ThreadStats& ts, const RayBatch& batch, int depth,
                 std::span<Vec3f> colors, PrimaryRecord* record);

}  // namespace rtt::render_detail
