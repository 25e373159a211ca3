#include "view/orbit_camera.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rtt::view {
namespace {

/// v rotated by `angle` about the unit axis k (Rodrigues).
Vec3f rotated(const Vec3f& v, const Vec3f& k, float angle) {
    const float c = std::cos(angle), s = std::sin(angle);
    return v * c + cross(k, v) * s + k * (dot(k, v) * (1.f - c));
}

}  // namespace

OrbitCamera::OrbitCamera(const Camera& start, float scene_size)
    : start_(start), camera_(start), scene_size_(scene_size > 0.f ? scene_size : 1.f) {}

void OrbitCamera::orbit(float yaw, float pitch) {
    const Vec3f up = normalize(camera_.up);
    Vec3f offset = camera_.position - camera_.target;
    const float distance = length(offset);
    if (!(distance > 0.f)) return;
    offset = rotated(offset, up, yaw);
    // Clamp the pitch so that the view stays at least a degree away from the up axis.
    const float limit = 3.14159265f / 180.f;
    const float polar = std::acos(std::clamp(dot(offset / distance, up), -1.f, 1.f));
    const float new_polar = std::clamp(polar - pitch, limit, 3.14159265f - limit);
    const Vec3f side = cross(up, offset);
    if (length(side) > 0.f) offset = rotated(offset, normalize(side), new_polar - polar);
    camera_.position = camera_.target + offset;
}

void OrbitCamera::pan(float right, float up) {
    const Vec3f view = camera_.target - camera_.position;
    const float distance = length(view);
    const Vec3f forward = view / distance;
    const Vec3f side = normalize(cross(forward, camera_.up));
    const Vec3f up2 = cross(side, forward);
    const float height = 2.f * distance * std::tan(camera_.fovy_deg * 3.14159265f / 360.f);
    const Vec3f move = (side * right + up2 * up) * height;
    camera_.position += move;
    camera_.target += move;
}

void OrbitCamera::dolly(float steps) {
    const Vec3f offset = camera_.position - camera_.target;
    const float distance = length(offset);
    const float wanted = std::max(distance * std::pow(0.9f, steps), 1e-4f * scene_size_);
    camera_.position = camera_.target + offset * (wanted / distance);
}

void OrbitCamera::fly(float forward, float right, float up) {
    const Vec3f f = normalize(camera_.target - camera_.position);
    const Vec3f side = normalize(cross(f, camera_.up));
    const Vec3f move = (f * forward + side * right + normalize(camera_.up) * up) * scene_size_;
    camera_.position += move;
    camera_.target += move;
}

std::string camera_string(const Camera& c) {
    // 9 significant digits give every float back exactly.
    char text[256];
    std::snprintf(text, sizeof text, "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g",
                  double(c.position.x), double(c.position.y), double(c.position.z),
                  double(c.target.x), double(c.target.y), double(c.target.z), double(c.up.x),
                  double(c.up.y), double(c.up.z), double(c.fovy_deg));
    return text;
}

}  // namespace rtt::view
