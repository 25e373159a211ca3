// Curved primitives: surfaces of revolution (and the cylinders and spheres built on them),
// tori, swept tubes and leaves.
#include <cmath>
#include <vector>

#include "builtin_scenes/procedural.h"
#include "core/check.h"

namespace rtt::proc {

namespace {

struct Angles {
    std::vector<float> c, s;
};

/// cos and sin of 2 pi j / n, j = 0 .. n - 1, evaluated once per primitive.
Angles angles(int n) {
    Angles a;
    for (int j = 0; j < n; ++j) {
        const double phi = 2.0 * 3.14159265358979323846 * double(j) / double(n);
        a.c.push_back(float(std::cos(phi)));
        a.s.push_back(float(std::sin(phi)));
    }
    return a;
}

/// Lathe with optional exact profile normals (else averaged from the adjacent segments).
Mesh lathe_impl(std::span<const Vec2f> profile, std::span<const Vec2f> profile_normals,
                int segments, Shading shading) {
    RTT_CHECK(profile.size() >= 2 && segments >= 3);
    const size_t np = profile.size();
    // Outward normal of segment k, from p[k] to p[k+1] (zero when the segment is degenerate,
    // which marks a crease).
    std::vector<Vec2f> seg(np - 1);
    for (size_t k = 0; k + 1 < np; ++k) {
        const float dr = profile[k + 1].x - profile[k].x, dy = profile[k + 1].y - profile[k].y;
        const float len = std::sqrt(dr * dr + dy * dy);
        seg[k] = len > 0.f ? Vec2f{dy / len, -dr / len} : Vec2f{};
    }
    const Angles ang = angles(segments);
    const auto ns = uint32_t(segments);
    Mesh m;
    for (size_t k = 0; k < np; ++k) {
        Vec2f n2;
        if (!profile_normals.empty()) {
            n2 = profile_normals[k];
        } else {
            if (k > 0) n2 = {n2.x + seg[k - 1].x, n2.y + seg[k - 1].y};
            if (k + 1 < np) n2 = {n2.x + seg[k].x, n2.y + seg[k].y};
        }
        const float len = std::sqrt(n2.x * n2.x + n2.y * n2.y);
        const bool smooth = shading == Shading::smooth && len > 0.f;
        for (uint32_t j = 0; j < ns; ++j) {
            const Vec3f p{profile[k].x * ang.c[j], profile[k].y, profile[k].x * ang.s[j]};
            const Vec3f n = smooth ? Vec3f{n2.x / len * ang.c[j], n2.y / len, n2.x / len * ang.s[j]}
                                   : Vec3f{0.f};
            m.add_vertex(p, n);
        }
    }
    for (size_t k = 0; k + 1 < np; ++k) {
        const bool pole0 = profile[k].x == 0.f, pole1 = profile[k + 1].x == 0.f;
        const bool same = profile[k].x == profile[k + 1].x && profile[k].y == profile[k + 1].y;
        if (same || (pole0 && pole1)) continue;
        for (uint32_t j = 0; j < ns; ++j) {
            const uint32_t a = uint32_t(k) * ns + j, b = uint32_t(k) * ns + (j + 1) % ns;
            const uint32_t d = a + ns, c = b + ns;
            // On the axis the quad collapses into one triangle.
            if (!pole0) m.add_triangle(a, c, b);
            if (!pole1) m.add_triangle(a, d, c);
        }
    }
    return m;
}

}  // namespace

Mesh lathe(std::span<const Vec2f> profile, int segments, Shading shading) {
    return lathe_impl(profile, {}, segments, shading);
}

Mesh cylinder(float r_bottom, float r_top, float height, int segments, bool cap_bottom,
              bool cap_top) {
    std::vector<Vec2f> p;
    if (cap_bottom) p.push_back({0.f, 0.f});
    p.push_back({r_bottom, 0.f});
    if (cap_bottom) p.push_back({r_bottom, 0.f});  // crease between cap and side
    p.push_back({r_top, height});
    if (cap_top && r_top > 0.f) {
        p.push_back({r_top, height});
        p.push_back({0.f, height});
    }
    return lathe(p, segments, Shading::smooth);
}

Mesh sphere(float r, int segments, int rings) {
    RTT_CHECK(rings >= 2);
    std::vector<Vec2f> p, n;
    for (int k = 0; k <= rings; ++k) {
        const double theta = 3.14159265358979323846 * double(k) / double(rings);
        const float s = (k == 0 || k == rings) ? 0.f : float(std::sin(theta));
        const float c = float(-std::cos(theta));
        p.push_back({r * s, r * c});
        n.push_back({s, c});
    }
    return lathe_impl(p, n, segments, Shading::smooth);
}

Mesh torus(float major, float minor, int segments, int sides) {
    const Angles phi = angles(segments), theta = angles(sides);
    Mesh m;
    for (int i = 0; i < segments; ++i)
        for (int j = 0; j < sides; ++j) {
            const float ring = major + minor * theta.c[size_t(j)];
            const Vec3f n{theta.c[size_t(j)] * phi.c[size_t(i)], theta.s[size_t(j)],
                          theta.c[size_t(j)] * phi.s[size_t(i)]};
            m.add_vertex(
                {ring * phi.c[size_t(i)], minor * theta.s[size_t(j)], ring * phi.s[size_t(i)]}, n);
        }
    const auto ns = uint32_t(sides), nseg = uint32_t(segments);
    for (uint32_t i = 0; i < nseg; ++i)
        for (uint32_t j = 0; j < ns; ++j) {
            const uint32_t i1 = (i + 1) % nseg, j1 = (j + 1) % ns;
            m.add_quad(i * ns + j, i * ns + j1, i1 * ns + j1, i1 * ns + j);
        }
    return m;
}

Mesh tube(std::span<const Vec3f> path, std::span<const float> radii, int sides, bool caps) {
    RTT_CHECK(path.size() >= 2 && radii.size() == path.size() && sides >= 3);
    const size_t np = path.size();
    const Angles ang = angles(sides);
    const auto ns = uint32_t(sides);
    Mesh m;
    Vec3f normal;
    for (size_t i = 0; i < np; ++i) {
        const Vec3f tangent = normalize(path[std::min(i + 1, np - 1)] - path[i > 0 ? i - 1 : 0]);
        if (i == 0) {
            // Start from the axis least aligned with the tangent.
            const Vec3f ta = abs(tangent);
            const Vec3f axis = (ta.x <= ta.y && ta.x <= ta.z) ? Vec3f{1.f, 0.f, 0.f}
                               : (ta.y <= ta.z)               ? Vec3f{0.f, 1.f, 0.f}
                                                              : Vec3f{0.f, 0.f, 1.f};
            normal = normalize(cross(tangent, axis));
        } else {
            // Parallel transport: remove the component along the new tangent.
            normal = normalize(normal - tangent * dot(normal, tangent));
        }
        const Vec3f binormal = cross(tangent, normal);
        for (uint32_t j = 0; j < ns; ++j) {
            const Vec3f dir = normal * ang.c[j] + binormal * ang.s[j];
            m.add_vertex(path[i] + dir * radii[i], dir);
        }
    }
    for (uint32_t i = 0; i + 1 < uint32_t(np); ++i)
        for (uint32_t j = 0; j < ns; ++j) {
            const uint32_t j1 = (j + 1) % ns;
            m.add_quad(i * ns + j, i * ns + j1, (i + 1) * ns + j1, (i + 1) * ns + j);
        }
    if (caps) {
        // Flat caps get their own vertices, so the rim is a crease. Ring order runs from the
        // normal towards the binormal, i.e. counter-clockwise about the tangent.
        for (int end = 0; end < 2; ++end) {
            const uint32_t ring = end == 0 ? 0u : uint32_t(np - 1) * ns;
            const auto centre = m.add_vertex(end == 0 ? path.front() : path.back());
            const auto base = uint32_t(m.vertices.size());
            for (uint32_t j = 0; j < ns; ++j) m.add_vertex(m.vertices[ring + j]);
            for (uint32_t j = 0; j < ns; ++j) {
                const uint32_t j1 = (j + 1) % ns;
                if (end == 0)
                    m.add_triangle(centre, base + j1, base + j);
                else
                    m.add_triangle(centre, base + j, base + j1);
            }
        }
    }
    return m;
}

std::vector<Vec3f> rounded_polyline(std::span<const Vec3f> corners, float radius, int steps) {
    RTT_CHECK(corners.size() >= 2 && steps >= 1);
    std::vector<Vec3f> out{corners.front()};
    for (size_t i = 1; i + 1 < corners.size(); ++i) {
        const Vec3f prev = corners[i - 1], c = corners[i], next = corners[i + 1];
        const float l0 = length(c - prev), l1 = length(next - c);
        const float r = std::min(radius, 0.5f * std::min(l0, l1));
        const Vec3f a = c + (prev - c) * (r / l0), b = c + (next - c) * (r / l1);
        for (int k = 0; k <= steps; ++k) {
            const float t = float(k) / float(steps);
            out.push_back(a * ((1.f - t) * (1.f - t)) + c * (2.f * t * (1.f - t)) + b * (t * t));
        }
    }
    out.push_back(corners.back());
    return out;
}

Mesh leaf(float length, float width, float fold, float droop, int segments) {
    RTT_CHECK(segments >= 2);
    Mesh m;
    auto midrib = [&](float t) { return Vec3f{0.f, length * t, -droop * length * t * t}; };
    const uint32_t base = m.add_vertex(midrib(0.f));
    std::vector<uint32_t> left, centre, right;
    for (int k = 1; k < segments; ++k) {
        const float t = float(k) / float(segments);
        const float w = 0.5f * width * std::sin(pi * t);
        const Vec3f c = midrib(t);
        left.push_back(m.add_vertex(c + Vec3f{-w, 0.f, fold * w}));
        centre.push_back(m.add_vertex(c));
        right.push_back(m.add_vertex(c + Vec3f{w, 0.f, fold * w}));
    }
    const uint32_t tip = m.add_vertex(midrib(1.f));
    m.add_triangle(base, right[0], centre[0]);
    m.add_triangle(base, centre[0], left[0]);
    for (size_t k = 0; k + 1 < centre.size(); ++k) {
        m.add_quad(centre[k], right[k], right[k + 1], centre[k + 1]);
        m.add_quad(left[k], centre[k], centre[k + 1], left[k + 1]);
    }
    m.add_triangle(centre.back(), right.back(), tip);
    m.add_triangle(centre.back(), tip, left.back());
    return m;
}

}  // namespace rtt::proc
