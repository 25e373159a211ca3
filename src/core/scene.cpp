#include "rtt/scene.h"

#include <cmath>
#include <string>
#include <utility>

#include "rtt/error.h"
#include "rtt/memory_budget.h"

namespace rtt {
namespace {
/// Finite and >= 0 in every component (false for NaN).
bool non_negative(const Vec3f& v) {
    return is_finite(v) && v.x >= 0.f && v.y >= 0.f && v.z >= 0.f;
}
}  // namespace

Bbox3f Scene::bounds() const {
    Bbox3f box;
    for (const TriangleIndices& t : triangles)
        for (uint32_t v : t) box.extend(vertices[v]);
    return box;
}

uint32_t Scene::add_material(const Material& m) {
    materials.push_back(m);
    return uint32_t(materials.size() - 1);
}

void Scene::add_mesh(std::span<const Vec3f> verts, std::span<const TriangleIndices> tris,
                     uint32_t material, std::span<const Vec3f> mesh_normals) {
    // Instancing lets a small file ask for any number of triangles: refuse before growing.
    require_memory(
        scene_memory_bytes(vertices.size() + verts.size(), triangles.size() + tris.size()),
        "a scene of " + std::to_string(triangles.size() + tris.size()) + " triangles");
    const auto base = uint32_t(vertices.size());
    const bool had_normals = !normals.empty() || vertices.empty();
    vertices.insert(vertices.end(), verts.begin(), verts.end());
    // Normals are all-or-nothing per scene: fill the gap with zero vectors, which shading
    // reads as "use the geometric normal".
    if (!mesh_normals.empty() || !normals.empty()) {
        if (!had_normals) normals.resize(base, Vec3f{0.f});
        if (mesh_normals.size() == verts.size())
            normals.insert(normals.end(), mesh_normals.begin(), mesh_normals.end());
        else
            normals.resize(vertices.size(), Vec3f{0.f});
    }
    for (const TriangleIndices& t : tris) {
        triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
        triangle_material.push_back(material);
    }
}

Scene Scene::from_mesh(std::span<const Vec3f> verts, std::span<const TriangleIndices> tris,
                       std::string name) {
    Scene scene;
    scene.name = std::move(name);
    scene.add_mesh(verts, tris, scene.add_material(Material{}));
    validate(scene);
    return scene;
}

void validate(const Scene& scene) {
    const std::string where = scene.name.empty() ? "scene" : scene.name;
    if (scene.triangle_material.size() != scene.triangles.size())
        throw Error(where + ": one material index per triangle expected");
    if (scene.materials.empty()) throw Error(where + ": no materials");
    if (!scene.normals.empty() && scene.normals.size() != scene.vertices.size())
        throw Error(where + ": normals must be empty or one per vertex");
    for (size_t i = 0; i < scene.vertices.size(); ++i)
        if (!is_finite(scene.vertices[i]))
            throw Error(where + ": vertex " + std::to_string(i) +
                        " has a NaN or infinite coordinate");
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        for (uint32_t v : scene.triangles[i])
            if (v >= scene.vertices.size())
                throw Error(where + ": triangle " + std::to_string(i) + " uses vertex " +
                            std::to_string(v) + " but there are " +
                            std::to_string(scene.vertices.size()));
        if (scene.triangle_material[i] >= scene.materials.size())
            throw Error(where + ": triangle " + std::to_string(i) + " has material index " +
                        std::to_string(scene.triangle_material[i]) + " out of range");
    }
    if (scene.lights.size() > max_lights)
        throw Error(where + ": " + std::to_string(scene.lights.size()) + " lights; at most " +
                    std::to_string(max_lights) + " are supported");
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        const Light& l = scene.lights[i];
        if (!is_finite(l.position) || !is_finite(l.direction) || !is_finite(l.color) ||
            !std::isfinite(l.intensity))
            throw Error(where + ": light " + std::to_string(i) + " has a NaN or infinite value");
        if (!non_negative(l.color) || !(l.intensity >= 0.f))
            throw Error(where + ": light " + std::to_string(i) +
                        " has a negative colour or intensity");
        if (!(l.inner_angle_deg >= 0.f && l.inner_angle_deg <= l.outer_angle_deg &&
              l.outer_angle_deg <= 180.f))
            throw Error(where + ": light " + std::to_string(i) +
                        " needs 0 <= inner angle <= outer angle <= 180 degrees");
    }
    for (size_t i = 0; i < scene.materials.size(); ++i) {
        const Material& m = scene.materials[i];
        if (!non_negative(m.diffuse) || !non_negative(m.specular) || !(m.shininess >= 0.f) ||
            !std::isfinite(m.shininess) || !(m.mirror >= 0.f && m.mirror <= 1.f))
            throw Error(where + ": material " + std::to_string(i) + " (" + m.name +
                        ") has a NaN, infinite or out-of-range value");
    }
    if (scene.camera) {
        const Camera& c = *scene.camera;
        if (!is_finite(c.position) || !is_finite(c.target) || !is_finite(c.up) ||
            !(c.fovy_deg > 0.f && c.fovy_deg < 180.f))
            throw Error(where + ": camera has a NaN or infinite value, or fovy outside (0, 180)");
    }
}

}  // namespace rtt
