// Primary rays exactly as CONVENTIONS writes them. This file is compiled, like all of rtt,
// with -ffp-contract=off: each expression is evaluated as written, in 32-bit float.
#include "rtt/camera.h"

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "core/check.h"
#include "geom/camera_simd.h"
#include "rtt/error.h"

namespace rtt {
namespace {

// The rays of a camera tile of width x height samples, row-major, t in [0, inf).
void camera_rays(const CameraTile& tile, int width, int height, std::span<Ray> out) {
    constexpr int K = simd_max_width;
    RTT_CHECK_EQ(out.size(), size_t(width) * size_t(height));
    const CameraFrame& f = *tile.frame;
    // Column factors padded to whole vectors (the padding lanes are computed and dropped).
    std::vector<float> a(size_t((width + K - 1) / K * K));
    column_factors(tile, width, a.data());
    for (size_t c = size_t(width); c < a.size(); ++c) a[c] = a[size_t(width) - 1];
    alignas(64) float dx[K], dy[K], dz[K];
    for (int sr = 0; sr < height; ++sr) {
        const float b = row_factor(tile, sr);
        Ray* row = out.data() + size_t(sr) * size_t(width);
        for (int sc = 0; sc < width; sc += K) {
            const Vec3v<K> d = camera_directions<K>(f, vfloat<K>::loadu(&a[size_t(sc)]), b);
            store(dx, d.x);
            store(dy, d.y);
            store(dz, d.z);
            for (int l = 0; l < K && sc + l < width; ++l)
                row[sc + l] = Ray{f.position, Vec3f{dx[l], dy[l], dz[l]}, 0.f, pos_inf};
        }
    }
}

}  // namespace

CameraRays::CameraRays(const Camera& camera, int width, int height, int aa) {
    if (width <= 0 || height <= 0) throw Error("image size must be positive");
    if (aa <= 0) throw Error("antialiasing factor must be positive");
    if (!is_finite(camera.position) || !is_finite(camera.target) || !is_finite(camera.up) ||
        !std::isfinite(camera.fovy_deg))
        throw Error("camera has a NaN or infinite value");
    if (!(camera.fovy_deg > 0.f && camera.fovy_deg < 180.f))
        throw Error("camera fovy must be in (0, 180) degrees");
    const Vec3f view = camera.target - camera.position;
    if (dot(view, view) == 0.f) throw Error("camera target equals its position");
    CameraFrame& f = frame_;
    f.position = camera.position;
    f.width = width;
    f.height = height;
    f.aa = aa;
    f.forward = normalize(view);
    // The formulas are CONVENTIONS' and stay as written; but in float a vector longer than about
    // 1e19 (its squared length overflows) or shorter than about 1e-19 (it underflows) normalizes
    // to zero, NaN or a non-unit vector, and every ray would silently go the same way.
    const auto unit = [](const Vec3f& v) { return std::fabs(length(v) - 1.f) <= 1e-4f; };
    if (!unit(f.forward))
        throw Error(
            "camera target - position must have a length between about 1e-18 and 1e18 "
            "(float cannot normalize it otherwise)");
    const Vec3f side = cross(f.forward, camera.up);
    if (!(dot(side, side) > 0.f)) throw Error("camera up vector is parallel to the view direction");
    f.right = normalize(side);
    f.up2 = cross(f.right, f.forward);
    if (!unit(f.right))
        throw Error(
            "camera up vector is nearly parallel to the view direction, or its length is "
            "outside about 1e-18..1e18 (float cannot normalize it)");
    f.aspect = float(width) / float(height);
    const float radians = camera.fovy_deg * (std::numbers::pi_v<float> / 180.f);
    f.h = std::tan(radians / 2.f);
}

void CameraRays::tile_rays(int tx, int ty, std::span<Ray> out) const {
    region_rays(tx, ty, 1, 1, out);
}

void CameraRays::region_rays(int tx, int ty, int cols, int rows, std::span<Ray> out) const {
    const int w = 4 * frame_.aa * cols, h = 4 * frame_.aa * rows;
    RTT_CHECK_EQ(out.size(), size_t(w) * size_t(h));
    camera_rays(tile(tx, ty), w, h, out);
}

Camera default_camera_for(const Bbox3f& scene_box, float fovy_deg) {
    // An empty scene is framed as the cube [-1, 1]^3.
    const Bbox3f box = scene_box.empty() ? Bbox3f{Vec3f{-1.f}, Vec3f{1.f}} : scene_box;
    const Vec3f c = box.center();
    const Vec3f d = box.diagonal();
    float radius = 0.5f * length(d);
    if (!(radius > 0.f)) radius = 1.f;
    const float half = fovy_deg * (std::numbers::pi_v<float> / 360.f);
    const float dist = radius / std::sin(half) * 1.05f;
    // From the front-right-top diagonal, y up.
    const Vec3f dir = normalize(Vec3f{1.f, 0.6f, 1.3f});
    return Camera{c + dir * dist, c, Vec3f{0.f, 1.f, 0.f}, fovy_deg};
}

}  // namespace rtt
