// The Embree comparison tracers: Intel Embree 3 answering exactly the same tiles of rays and
// shadow segments as our kd-tree tracers, so benchmarks compare like with like.
//
//  * "embree":  each tile is cut into 4x4 blocks of its sample grid, one rtcIntersect16 /
//               rtcOccluded16 per block, in coherent mode (RTC_INTERSECT_CONTEXT_FLAG_COHERENT):
//               Embree's frustum-culled packet traversal, its best case for camera rays at K = 1.
//  * "embree-stream": one rtcIntersect1M / rtcOccluded1M per tile (its active segments), the
//               rays in the tile's order, coherent mode: Embree 3's stream path, which groups
//               them by octant into large frusta itself; its best case at K = 4 on dense meshes.
//  * "embree1": rtcIntersect1 / rtcOccluded1 per ray, Embree's single-ray kernels.
// Each with build quality HIGH (SAH with spatial splits), and as "<kind>-medium" with MEDIUM,
// Embree's default, which builds several times faster.
//
// Scene: one triangle geometry holding the scene's vertices and indices unchanged, so Embree's
// primID is our triangle index (CONVENTIONS).
// Scene flags: none, Embree's default fast mode. RTC_SCENE_FLAG_ROBUST (Pluecker triangle test,
// conservative box tests) would close most of its holes on shared edges, but traces 10-13 %
// slower and makes Embree 3.13 ignore the HIGH build quality (robust scenes get the plain SAH
// builder); the question this tracer answers is "how fast is the state of the art", so it runs
// as Embree's users run it. docs/benchmarks.md ("Embree") has the measurements.
//
// Exactness: Embree has its own ray/triangle arithmetic, so it may pick the other triangle of
// an exact tie (shared edge or vertex, coplanar overlap) or miss/hit a ray grazing an edge by a
// rounding error; tests/embree_test.cpp counts those and requires every other answer to match
// the brute-force oracle. Hit::t is Embree's own distance, not the watertight test's.
//
// Threads: one RTCDevice per tracer; rtcIntersect*/rtcOccluded* are thread-safe on a committed
// scene, so tiles may be traced concurrently from the renderer's oneTBB workers.
#include "trace/trace_embree.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "rtt/error.h"
#include "trace/factories.h"
#include "trace/traced_tile.h"

namespace rtt {
namespace {

struct DeviceRelease {
    void operator()(RTCDevice d) const { rtcReleaseDevice(d); }
};
struct SceneRelease {
    void operator()(RTCScene s) const { rtcReleaseScene(s); }
};
using DeviceHandle = std::unique_ptr<RTCDeviceTy, DeviceRelease>;
using SceneHandle = std::unique_ptr<RTCSceneTy, SceneRelease>;

/// Device-wide state reached from Embree's callbacks.
struct DeviceLog {
    std::mutex mutex;
    std::string first_error;        ///< First message Embree reported, if any.
    std::atomic<int64_t> bytes{0};  ///< Net bytes the device holds (memory monitor).
};

void on_error(void* user, RTCError code, const char* message) {
    auto* log = static_cast<DeviceLog*>(user);
    std::lock_guard lock(log->mutex);
    if (log->first_error.empty())
        log->first_error =
            "embree error " + std::to_string(int(code)) + ": " + (message ? message : "");
}

bool on_memory(void* user, ssize_t bytes, bool /*post*/) {
    static_cast<DeviceLog*>(user)->bytes += bytes;
    return true;  // never veto an allocation
}

/// Rays per Embree packet: one 4x4 block of the tile's sample grid.
constexpr int block = 4;
constexpr int lanes = block * block;

/// Lane l of a block at (bx, by) is sample (bx + l % 4, by + l / 4); -1 when that sample lies
/// outside the tile (a tile whose size is not a multiple of 4).
int lane_index(int width, int height, int bx, int by, int l) {
    const int x = bx + l % block, y = by + l / block;
    return x < width && y < height ? y * width + x : -1;
}

template <typename RayK>
void set_lane(RayK& r, int l, const Ray& ray) {
    r.org_x[l] = ray.org.x;
    r.org_y[l] = ray.org.y;
    r.org_z[l] = ray.org.z;
    r.tnear[l] = ray.tmin;
    r.dir_x[l] = ray.dir.x;
    r.dir_y[l] = ray.dir.y;
    r.dir_z[l] = ray.dir.z;
    r.time[l] = 0.f;
    r.tfar[l] = ray.tmax;
    r.mask[l] = 0xFFFFFFFFu;
    r.id[l] = unsigned(l);
    r.flags[l] = 0;
}

void set_ray(RTCRay& r, const Ray& ray) {
    r.org_x = ray.org.x;
    r.org_y = ray.org.y;
    r.org_z = ray.org.z;
    r.tnear = ray.tmin;
    r.dir_x = ray.dir.x;
    r.dir_y = ray.dir.y;
    r.dir_z = ray.dir.z;
    r.time = 0.f;
    r.tfar = ray.tmax;
    r.mask = 0xFFFFFFFFu;
    r.id = 0;
    r.flags = 0;
}

/// A ray Embree answers: a non-empty interval (tmax < tmin marks an inactive lane).
bool active(const Ray& ray) {
    return ray.tmin <= ray.tmax;
}

/// The placeholder for a lane outside the tile or inactive (valid = 0, never traced, but every
/// field is finite so no lane of Embree's SIMD code sees garbage).
constexpr Ray idle_ray{Vec3f{0.f}, Vec3f{0.f, 0.f, 1.f}, 0.f, 0.f};

class EmbreeTracer final : public Tracer, public OwnAccelerationInfo {
public:
    EmbreeTracer(const Scene& scene, EmbreeMode mode, bool medium)
        : log_(std::make_unique<DeviceLog>()), mode_(mode), medium_(medium) {
        const RTCBuildQuality quality = medium ? RTC_BUILD_QUALITY_MEDIUM : RTC_BUILD_QUALITY_HIGH;
        device_.reset(rtcNewDevice(nullptr));
        if (!device_)
            throw Error("embree: cannot create a device (error " +
                        std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
        rtcSetDeviceErrorFunction(device_.get(), on_error, log_.get());
        rtcSetDeviceMemoryMonitorFunction(device_.get(), on_memory, log_.get());

        scene_.reset(rtcNewScene(device_.get()));
        rtcSetSceneFlags(scene_.get(), RTC_SCENE_FLAG_NONE);
        rtcSetSceneBuildQuality(scene_.get(), quality);
        if (scene.triangle_count() > 0) {
            RTCGeometry geom = rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
            rtcSetGeometryBuildQuality(geom, quality);
            // rtcSetNewGeometryBuffer pads the vertex buffer as Embree's 16-byte SIMD loads need.
            void* verts =
                rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                        sizeof(Vec3f), scene.vertices.size());
            void* ids = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                sizeof(TriangleIndices), scene.triangles.size());
            if (verts && ids) {
                static_assert(sizeof(Vec3f) == 3 * sizeof(float));
                static_assert(sizeof(TriangleIndices) == 3 * sizeof(uint32_t));
                std::memcpy(verts, scene.vertices.data(), scene.vertices.size() * sizeof(Vec3f));
                std::memcpy(ids, scene.triangles.data(),
                            scene.triangles.size() * sizeof(TriangleIndices));
                rtcCommitGeometry(geom);
                rtcAttachGeometry(scene_.get(), geom);  // geomID 0
            }
            rtcReleaseGeometry(geom);  // the scene keeps its own reference
        }
        throw_if_failed("setting up the scene");

        const auto start = std::chrono::steady_clock::now();
        rtcCommitScene(scene_.get());
        build_seconds_ =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        throw_if_failed("building the BVH");
    }

    std::string_view name() const override { return embree_kind_name(mode_, medium_); }
    bool reorders_batches() const override { return false; }
    double build_seconds() const override { return build_seconds_; }
    size_t memory_bytes() const override {
        return size_t(std::max<int64_t>(log_->bytes.load(), 0));
    }

    void intersect(const RayTile& tile, std::span<Hit> hits,
                   const TraceContext& context) const override {
        switch (mode_) {
            case EmbreeMode::packets:
                intersect16(tile, hits);
                break;
            case EmbreeMode::stream:
                intersect_stream(tile, hits);
                break;
            case EmbreeMode::single:
                intersect1(tile, hits);
                break;
        }
        record_traced_tile(tile.rays.size(), context);
    }

    void occluded(const SegmentTile& tile, std::span<uint8_t> visible,
                  const TraceContext& context) const override {
        const auto segment = [&](int i) {
            return tile.active[size_t(i)]
                       ? std::optional(shadow_ray(tile.light, tile.points[size_t(i)]))
                       : std::nullopt;
        };
        occluded_any(tile.width, tile.height, segment, visible);
        uint64_t n = 0;
        for (size_t i = 0; i < tile.points.size(); ++i) n += tile.active[i] != 0;
        record_traced_tile(n, context);
    }

    void visible_arbitrary(std::span<const Ray> rays, std::span<uint8_t> visible,
                           TraceStats* stats) const override {
        // Consecutive rays in 4-ray rows, so that a 4x4 block is 16 consecutive rays.
        const int n = int(rays.size());
        occluded_any(
            std::min(n, block), (n + block - 1) / block,
            [&](int i) { return i < n ? std::optional(rays[size_t(i)]) : std::nullopt; }, visible);
        record_traced_tile(rays.size(), stats);
    }

private:
    void throw_if_failed(const char* what) const {
        const RTCError code = rtcGetDeviceError(device_.get());
        std::lock_guard lock(log_->mutex);
        if (code != RTC_ERROR_NONE || !log_->first_error.empty())
            throw Error(std::string("embree: failed ") + what + ": " +
                        (log_->first_error.empty() ? "error " + std::to_string(int(code))
                                                   : log_->first_error));
    }

    static RTCIntersectContext coherent_context() {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        return ctx;
    }

    void intersect16(const RayTile& tile, std::span<Hit> hits) const {
        RTCIntersectContext ctx = coherent_context();
        alignas(64) RTCRayHit16 rh;
        alignas(64) int valid[lanes];
        int index[lanes];
        for (int by = 0; by < tile.height; by += block) {
            for (int bx = 0; bx < tile.width; bx += block) {
                for (int l = 0; l < lanes; ++l) {
                    index[l] = lane_index(tile.width, tile.height, bx, by, l);
                    const Ray& ray = index[l] >= 0 ? tile.rays[index[l]] : idle_ray;
                    const bool on = index[l] >= 0 && active(ray);
                    valid[l] = on ? -1 : 0;
                    set_lane(rh.ray, l, on ? ray : idle_ray);
                    rh.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
                    rh.hit.instID[0][l] = RTC_INVALID_GEOMETRY_ID;
                }
                rtcIntersect16(valid, scene_.get(), &ctx, &rh);
                for (int l = 0; l < lanes; ++l) {
                    if (index[l] < 0) continue;
                    hits[index[l]] = valid[l] && rh.hit.geomID[l] != RTC_INVALID_GEOMETRY_ID
                                         ? Hit{rh.ray.tfar[l], rh.hit.primID[l]}
                                         : Hit{};
                }
            }
        }
    }

    // The stream kernels take an array of rays; one call per tile, in the tile's order. The
    // array is per thread (tiles are traced concurrently) and reused from tile to tile.
    void intersect_stream(const RayTile& tile, std::span<Hit> hits) const {
        thread_local std::vector<RTCRayHit> rays;
        thread_local std::vector<uint32_t> index;
        RTCIntersectContext ctx = coherent_context();
        rays.clear();
        index.clear();
        for (size_t i = 0; i < tile.rays.size(); ++i) {
            hits[i] = Hit{};
            if (!active(tile.rays[i])) continue;
            RTCRayHit& rh = rays.emplace_back();
            set_ray(rh.ray, tile.rays[i]);
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            index.push_back(uint32_t(i));
        }
        if (rays.empty()) return;
        rtcIntersect1M(scene_.get(), &ctx, rays.data(), unsigned(rays.size()), sizeof(RTCRayHit));
        for (size_t j = 0; j < rays.size(); ++j)
            if (rays[j].hit.geomID != RTC_INVALID_GEOMETRY_ID)
                hits[index[j]] = Hit{rays[j].ray.tfar, rays[j].hit.primID};
    }

    void intersect1(const RayTile& tile, std::span<Hit> hits) const {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        for (size_t i = 0; i < tile.rays.size(); ++i) {
            hits[i] = Hit{};
            if (!active(tile.rays[i])) continue;
            RTCRayHit rh;
            set_ray(rh.ray, tile.rays[i]);
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(scene_.get(), &ctx, &rh);
            if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) hits[i] = Hit{rh.ray.tfar, rh.hit.primID};
        }
    }

    // Any-hit in the tracer's mode over a width x height grid of rays; ray_of(i) gives sample
    // i's ray, or nothing (visible 0). rtcOccluded* marks an occluded ray with tfar = -inf.
    template <typename RayOf>
    void occluded_any(int width, int height, const RayOf& ray_of,
                      std::span<uint8_t> visible) const {
        switch (mode_) {
            case EmbreeMode::packets:
                return occluded16(width, height, ray_of, visible);
            case EmbreeMode::stream:
                return occluded_stream(width * height, ray_of, visible);
            case EmbreeMode::single:
                return occluded1(width * height, ray_of, visible);
        }
    }

    template <typename RayOf>
    void occluded16(int width, int height, const RayOf& ray_of, std::span<uint8_t> visible) const {
        RTCIntersectContext ctx = coherent_context();
        alignas(64) RTCRay16 r;
        alignas(64) int valid[lanes];
        int index[lanes];
        for (int by = 0; by < height; by += block) {
            for (int bx = 0; bx < width; bx += block) {
                for (int l = 0; l < lanes; ++l) {
                    index[l] = lane_index(width, height, bx, by, l);
                    const std::optional<Ray> ray = index[l] >= 0 ? ray_of(index[l]) : std::nullopt;
                    valid[l] = ray ? -1 : 0;
                    set_lane(r, l, ray ? *ray : idle_ray);
                }
                rtcOccluded16(valid, scene_.get(), &ctx, &r);
                for (int l = 0; l < lanes; ++l)
                    if (index[l] >= 0 && size_t(index[l]) < visible.size())
                        visible[size_t(index[l])] = valid[l] && r.tfar[l] != neg_inf;
            }
        }
    }

    // The stream kernels take an array of rays; one call per tile, in the tile's order. The
    // array is per thread (tiles are traced concurrently) and reused from tile to tile.
    template <typename RayOf>
    void occluded_stream(int n, const RayOf& ray_of, std::span<uint8_t> visible) const {
        thread_local std::vector<RTCRay> rays;
        thread_local std::vector<uint32_t> index;
        RTCIntersectContext ctx = coherent_context();
        rays.clear();
        index.clear();
        for (int i = 0; i < n; ++i) {
            const std::optional<Ray> ray = ray_of(i);
            if (size_t(i) < visible.size()) visible[size_t(i)] = 0;
            if (!ray) continue;
            set_ray(rays.emplace_back(), *ray);
            index.push_back(uint32_t(i));
        }
        if (rays.empty()) return;
        rtcOccluded1M(scene_.get(), &ctx, rays.data(), unsigned(rays.size()), sizeof(RTCRay));
        for (size_t j = 0; j < rays.size(); ++j) visible[index[j]] = rays[j].tfar != neg_inf;
    }

    template <typename RayOf>
    void occluded1(int n, const RayOf& ray_of, std::span<uint8_t> visible) const {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        for (int i = 0; i < n; ++i) {
            const std::optional<Ray> ray = ray_of(i);
            if (size_t(i) < visible.size()) visible[size_t(i)] = 0;
            if (!ray) continue;
            RTCRay r;
            set_ray(r, *ray);
            rtcOccluded1(scene_.get(), &ctx, &r);
            visible[size_t(i)] = r.tfar != neg_inf;
        }
    }

    std::unique_ptr<DeviceLog> log_;  // outlives device_: Embree's callbacks point into it
    DeviceHandle device_;
    SceneHandle scene_;
    EmbreeMode mode_;
    bool medium_;
    double build_seconds_ = 0.0;
};

}  // namespace

std::unique_ptr<Tracer> make_embree_tracer(const Scene& scene, EmbreeMode mode, bool medium) {
    return std::make_unique<EmbreeTracer>(scene, mode, medium);
}

}  // namespace rtt
