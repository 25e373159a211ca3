// The scene model: one triangle mesh (meshes are merged in load order, so triangle indices
// follow CONVENTIONS), materials, lights, an optional camera and a background colour.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "rtt/math.h"

namespace rtt {

struct Material {
    std::string name = "default";
    Vec3f diffuse{0.7f};     ///< Lambertian colour, linear RGB in [0, 1].
    Vec3f specular{0.f};     ///< Phong specular colour.
    float shininess = 32.f;  ///< Phong exponent.
    float mirror = 0.f;      ///< Mirror reflectivity in [0, 1]; > 0 spawns reflected rays.
};

enum class LightKind { omni, spot };

struct Light {
    LightKind kind = LightKind::omni;
    Vec3f position;
    Vec3f direction{0.f, -1.f, 0.f};  ///< Spot axis (need not be normalized).
    float inner_angle_deg = 30.f;     ///< Spot: full intensity inside this half-angle.
    float outer_angle_deg = 45.f;     ///< Spot: no light outside this half-angle.
    Vec3f color{1.f};
    float intensity = 1.f;  ///< Radiant intensity; irradiance falls off as 1 / distance^2.
};

/// Pinhole camera of CONVENTIONS: position, target, up vector, vertical field of view.
struct Camera {
    Vec3f position{0.f, 0.f, 1.f};
    Vec3f target{0.f, 0.f, 0.f};
    Vec3f up{0.f, 1.f, 0.f};
    float fovy_deg = 60.f;
};

/// A camera a mesh file defines, with its name there ("" when it has none).
struct FileCamera {
    std::string name;
    Camera camera;
};

using TriangleIndices = std::array<uint32_t, 3>;

struct Scene {
    std::string name;
    std::vector<Vec3f> vertices;
    std::vector<TriangleIndices> triangles;   ///< Triangle i has index i (CONVENTIONS).
    std::vector<uint32_t> triangle_material;  ///< One material index per triangle.
    std::vector<Vec3f> normals;               ///< Empty, or one shading normal per vertex.
    std::vector<Material> materials;
    std::vector<Light> lights;
    std::optional<Camera> camera;
    /// Every perspective camera a mesh file defines, in file order (`camera` is the first);
    /// `rtt render FILE --camera N` picks one, `--list-cameras` lists them.
    std::vector<FileCamera> file_cameras;
    Vec3f background{0.05f, 0.05f, 0.08f};
    /// What an importer skipped or repaired ("file:line: face with 2 vertices skipped"): the
    /// first max_kept_warnings messages, and how many there were in all.
    std::vector<std::string> warnings;
    size_t warning_count = 0;
    static constexpr size_t max_kept_warnings = 16;
    void warn(std::string message) {
        if (warnings.size() < max_kept_warnings) warnings.push_back(std::move(message));
        ++warning_count;
    }

    size_t triangle_count() const { return triangles.size(); }
    Bbox3f bounds() const;

    /// Adds a material and returns its index.
    uint32_t add_material(const Material& m);
    /// Appends a mesh (the arrays are copied); its triangles get the next indices, in the given
    /// order, and their vertex indices are relative to `vertices`. `normals` is empty or one
    /// per vertex (a scene mixing both gets geometric normals where missing). Throws
    /// rtt::Error when the scene would not fit in memory; validate() checks the rest.
    void add_mesh(std::span<const Vec3f> vertices, std::span<const TriangleIndices> triangles,
                  uint32_t material, std::span<const Vec3f> normals = {});

    /// A scene of one mesh from arrays in memory, no file involved: a grey material, no lights,
    /// no camera. Validated: throws rtt::Error for an index out of range or a NaN
    /// or infinite coordinate.
    static Scene from_mesh(std::span<const Vec3f> vertices,
                           std::span<const TriangleIndices> triangles, std::string name = "mesh");
};

/// Throws rtt::Error when the scene cannot be rendered: indices out of range,
/// NaN or infinite coordinates, material indices out of range, more than 32 lights, NaN or
/// out-of-range material, light or camera values (negative colours, mirror outside [0, 1],
/// spot angles not 0 <= inner <= outer <= 180, fovy outside (0, 180)).
void validate(const Scene& scene);

/// Largest number of lights a scene may have (RTTS buffers keep one bit per light).
inline constexpr size_t max_lights = 32;

}  // namespace rtt
