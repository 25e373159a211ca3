// Local shading: Phong (diffuse + specular lobe) with omni and spot lights, spot fall-off as a
// smoothstep between the outer and inner cones, 1 / d^2 distance attenuation, a small ambient
// term. Shading runs after all rays of a tile were traced; none of it affects which rays are
// traced except can_light(), which decides the active shadow segments.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <numbers>

#include "render/render_internal.h"

namespace rtt {
namespace render_detail {
namespace {

/// Fraction of a surface's diffuse colour seen without any light (keeps shadows readable).
constexpr float ambient = 0.04f;

float smoothstep(float e0, float e1, float x) {
    if (!(e1 > e0)) return x > e0 ? 1.f : 0.f;
    const float t = std::clamp((x - e0) / (e1 - e0), 0.f, 1.f);
    return t * t * (3.f - 2.f * t);
}

float max_abs(const Vec3f& v) {
    return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
}

}  // namespace

Plane triangle_plane(const TriangleVerts& tri) {
    const Vec3f n = normalize(cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
    return {n, dot(n, tri.v0)};
}

RenderContext make_context(const Scene& scene, const Tracer& tracer, const RenderOptions& options,
                           const AnswerMaps& maps) {
    RenderContext ctx{scene, tracer, options, maps, {}, 0.f};
    for (const Light& l : scene.lights) {
        LightInfo info;
        info.light = &l;
        if (l.kind == LightKind::spot) {
            info.axis = normalize(l.direction);
            const float deg = std::numbers::pi_v<float> / 180.f;
            info.cos_outer = std::cos(l.outer_angle_deg * deg);
            info.cos_inner = std::cos(std::min(l.inner_angle_deg, l.outer_angle_deg) * deg);
        }
        ctx.lights.push_back(info);
    }
    // Packed reflected rays start at the hit point; the epsilon must exceed the rounding of
    // that point, which grows with the distance from the origin, and stay small against the
    // scene (1e-4 of its extent).
    const Bbox3f box = scene.bounds();
    const Vec3f d = box.diagonal();
    const float extent = std::max({d.x, d.y, d.z});
    const float magnitude = std::max(max_abs(box.lo), max_abs(box.hi));
    ctx.reflect_epsilon = 1e-4f * extent + 32.f * FLT_EPSILON * magnitude;
    if (!(ctx.reflect_epsilon > 0.f)) ctx.reflect_epsilon = 1e-6f;
    return ctx;
}

SurfacePoint surface_at(const RenderContext& ctx, const Ray& ray, const Hit& hit) {
    SurfacePoint s;
    s.p = ray.org + hit.t * ray.dir;
    const Scene& scene = ctx.scene;
    const TriangleVerts tri = triangle_verts(scene, hit.tri);
    s.material = &scene.materials[scene.triangle_material[hit.tri]];
    const Vec3f e1 = tri.v1 - tri.v0, e2 = tri.v2 - tri.v0;
    const Vec3f c = cross(e1, e2);
    const float len = length(c);
    // A degenerate triangle (hit edge-on) has no plane: shade it as facing the ray.
    s.ng = len > 0.f && std::isfinite(len) ? c / len : -normalize(ray.dir);
    if (dot(s.ng, ray.dir) > 0.f) s.ng = -s.ng;
    s.ns = s.ng;
    if (!scene.normals.empty()) {
        const TriangleIndices& idx = scene.triangles[hit.tri];
        const Vec3f n0 = scene.normals[idx[0]], n1 = scene.normals[idx[1]],
                    n2 = scene.normals[idx[2]];
        // A zero vertex normal means "no shading normal here" (Scene::add_mesh).
        const Vec3f zero{0.f};
        if (n0 != zero && n1 != zero && n2 != zero) {
            const Vec3f vp = s.p - tri.v0;
            const float d00 = dot(e1, e1), d01 = dot(e1, e2), d11 = dot(e2, e2);
            const float d20 = dot(vp, e1), d21 = dot(vp, e2);
            const float denom = d00 * d11 - d01 * d01;
            if (denom != 0.f) {
                const float b1 = (d11 * d20 - d01 * d21) / denom;
                const float b2 = (d00 * d21 - d01 * d20) / denom;
                const float b0 = 1.f - b1 - b2;
                const Vec3f n = n0 * b0 + n1 * b1 + n2 * b2;
                const float nl = length(n);
                if (nl > 0.f && std::isfinite(nl)) {
                    s.ns = n / nl;
                    if (dot(s.ns, ray.dir) > 0.f) s.ns = -s.ns;  // face the viewer
                }
            }
        }
    }
    return s;
}

bool can_light(const LightInfo& info, const SurfacePoint& s) {
    const Vec3f to_light = info.light->position - s.p;
    if (!(dot(s.ng, to_light) > 0.f)) return false;
    if (info.light->kind == LightKind::spot) {
        const float len = length(to_light);
        if (!(len > 0.f)) return false;
        const float cos_angle = -dot(to_light, info.axis) / len;
        if (!(cos_angle > info.cos_outer)) return false;
    }
    return true;
}

Vec3f shade(const RenderContext& ctx, const SurfacePoint& s, const Vec3f& dir, uint32_t lit) {
    const Material& m = *s.material;
    Vec3f c = m.diffuse * ambient;
    const Vec3f view = -normalize(dir);
    for (size_t l = 0; l < ctx.lights.size(); ++l) {
        if (!(lit >> l & 1u)) continue;
        const LightInfo& info = ctx.lights[l];
        const Light& light = *info.light;
        const Vec3f to_light = light.position - s.p;
        const float d2 = dot(to_light, to_light);
        if (!(d2 > 0.f)) continue;
        const Vec3f ld = to_light / std::sqrt(d2);
        const float ndotl = dot(s.ns, ld);
        if (!(ndotl > 0.f)) continue;
        float falloff = 1.f;
        if (light.kind == LightKind::spot)
            falloff = smoothstep(info.cos_outer, info.cos_inner, -dot(ld, info.axis));
        const Vec3f irradiance = light.color * (light.intensity * falloff / d2);
        const Vec3f r = s.ns * (2.f * ndotl) - ld;  // ld mirrored about the shading normal
        const float rv = std::max(0.f, dot(r, view));
        const Vec3f spec = m.specular * (rv > 0.f ? std::pow(rv, m.shininess) : 0.f);
        c += irradiance * (m.diffuse * ndotl + spec);
    }
    return c;
}

}  // namespace render_detail

Light make_point_light(const Vec3f& position, const Bbox3f& scene_bounds, size_t light_count) {
    Light l;
    l.kind = LightKind::omni;
    l.position = position;
    const float diag = scene_bounds.empty() ? 1.f : length(scene_bounds.diagonal());
    l.intensity = 0.5f * diag * diag / float(std::max<size_t>(light_count, 1));
    if (!(l.intensity > 0.f) || !std::isfinite(l.intensity)) l.intensity = 1.f;
    return l;
}

std::vector<uint8_t> encode_srgb8(const std::vector<Vec3f>& pixels) {
    std::vector<uint8_t> out(pixels.size() * 3);
    auto encode = [](float v) {
        v = std::isfinite(v) ? std::clamp(v, 0.f, 1.f) : 0.f;
        const float s = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.f / 2.4f) - 0.055f;
        return uint8_t(std::lround(s * 255.f));
    };
    for (size_t i = 0; i < pixels.size(); ++i) {
        out[3 * i] = encode(pixels[i].x);
        out[3 * i + 1] = encode(pixels[i].y);
        out[3 * i + 2] = encode(pixels[i].z);
    }
    return out;
}

}  // namespace rtt
