// Primary rays exactly as CONVENTIONS writes them. This file is compiled, like all of rtt,
// with -ffp-contract=off: each expression is evaluated as written, in 32-bit float.
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "core/check.h"
#include "rtt/camera.h"
#include "rtt/error.h"

namespace rtt {

CameraRays::CameraRays(const Camera& camera, int width, int height, int aa)
    : pos_(camera.position), width_(width), height_(height), aa_(aa) {
    if (width <= 0 || height <= 0) throw Error("image size must be positive");
    if (aa <= 0) throw Error("antialiasing factor must be positive");
    if (!is_finite(camera.position) || !is_finite(camera.target) || !is_finite(camera.up) ||
        !std::isfinite(camera.fovy_deg))
        throw Error("camera has a NaN or infinite value");
    if (!(camera.fovy_deg > 0.f && camera.fovy_deg < 180.f))
        throw Error("camera fovy must be in (0, 180) degrees");
    const Vec3f view = camera.target - camera.position;
    if (dot(view, view) == 0.f) throw Error("camera target equals its position");
    forward_ = normalize(view);
    // The formulas are CONVENTIONS' and stay as written; but in float a vector longer than about
    // 1e19 (its squared length overflows) or shorter than about 1e-19 (it underflows) normalizes
    // to zero, NaN or a non-unit vector, and every ray would silently go the same way.
    const auto unit = [](const Vec3f& v) { return std::fabs(length(v) - 1.f) <= 1e-4f; };
    if (!unit(forward_))
        throw Error("camera target - position must have a length between about 1e-18 and 1e18 "
                    "(float cannot normalize it otherwise)");
    const Vec3f side = cross(forward_, camera.up);
    if (!(dot(side, side) > 0.f)) throw Error("camera up vector is parallel to the view direction");
    right_ = normalize(side);
    up2_ = cross(right_, forward_);
    if (!unit(right_))
        throw Error("camera up vector is nearly parallel to the view direction, or its length is "
                    "outside about 1e-18..1e18 (float cannot normalize it)");
    aspect_ = float(width) / float(height);
    const float radians = camera.fovy_deg * (std::numbers::pi_v<float> / 180.f);
    h_ = std::tan(radians / 2.f);
}

Vec3f CameraRays::direction(int x, int y, int i, int j) const {
    const float k = float(aa_);
    const float u = (float(x) + (float(i) + 0.5f) / k) / float(width_);
    const float v = (float(y) + (float(j) + 0.5f) / k) / float(height_);
    const float a = (2.f * u - 1.f) * h_ * aspect_;
    const float b = (2.f * v - 1.f) * h_;
    return normalize(forward_ + a * right_ - b * up2_);
}

void CameraRays::tile_rays(int tx, int ty, std::span<Ray> out) const {
    region_rays(tx, ty, 1, 1, out);
}

void CameraRays::region_rays(int tx, int ty, int cols, int rows, std::span<Ray> out) const {
    const int k = aa_, w = 4 * k * cols, h = 4 * k * rows;
    RTT_CHECK_EQ(out.size(), size_t(w) * size_t(h));
    for (int sr = 0; sr < h; ++sr)
        for (int sc = 0; sc < w; ++sc)
            out[size_t(sr) * size_t(w) + size_t(sc)] =
                Ray{pos_, direction(tx * 4 + sc / k, ty * 4 + sr / k, sc % k, sr % k), 0.f, pos_inf};
}

Camera default_camera_for(const Bbox3f& box, float fovy_deg) {
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
