// Procedural mesh primitives for the built-in scenes: boxes, rounded boxes, surfaces of
// revolution, tubes swept along paths, extruded profiles and leaves, placed by affine
// transforms and collected per material into a Scene.
//
// Everything here is deterministic: the same calls produce the same vertices, bit for bit
// (plain float arithmetic and libm's sin/cos only; random numbers come from SceneRng, which
// derives floats from std::mt19937's integers itself because std::uniform_real_distribution
// is not specified identically across standard libraries).
//
// Orientation: every closed primitive is wound counter-clockwise seen from outside, so
// cross(b - a, c - a) points outward. Normals: each vertex carries a shading normal; a zero
// normal means "use the geometric normal" (scene.h), which is what flat shading emits.
#pragma once

#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include "rtt/math.h"
#include "rtt/scene.h"

namespace rtt::proc {

inline constexpr float pi = 3.14159265358979323846f;

/// Degrees to radians.
constexpr float radians(float deg) {
    return deg * (pi / 180.f);
}

struct Vec2f {
    float x = 0.f, y = 0.f;
};

/// Affine map p -> c0 * p.x + c1 * p.y + c2 * p.z + t (columns c0, c1, c2).
struct Xform {
    Vec3f c0{1.f, 0.f, 0.f}, c1{0.f, 1.f, 0.f}, c2{0.f, 0.f, 1.f};
    Vec3f t{0.f};

    Vec3f point(const Vec3f& p) const { return c0 * p.x + c1 * p.y + c2 * p.z + t; }
    Vec3f vector(const Vec3f& v) const { return c0 * v.x + c1 * v.y + c2 * v.z; }
    /// Transforms a normal by the cofactor matrix (the inverse transpose up to a positive
    /// factor for orientation-preserving maps) and normalizes it; a zero normal stays zero.
    Vec3f normal(const Vec3f& n) const;
    /// This map applied after `inner`.
    Xform operator*(const Xform& inner) const;

    static Xform translate(const Vec3f& d);
    static Xform scale(const Vec3f& s);
    static Xform rotate_x(float radians);
    static Xform rotate_y(float radians);
    static Xform rotate_z(float radians);
    /// Maps the local axes to x, y, z and the local origin to `origin`.
    static Xform basis(const Vec3f& x, const Vec3f& y, const Vec3f& z, const Vec3f& origin);
};

enum class Shading { flat, smooth };

/// An indexed triangle mesh with one shading normal per vertex (zero = geometric normal).
struct Mesh {
    std::vector<Vec3f> vertices;
    std::vector<Vec3f> normals;
    std::vector<TriangleIndices> triangles;

    uint32_t add_vertex(const Vec3f& p, const Vec3f& n = Vec3f{0.f});
    void add_triangle(uint32_t a, uint32_t b, uint32_t c) { triangles.push_back({a, b, c}); }
    /// Two triangles (a, b, c), (a, c, d).
    void add_quad(uint32_t a, uint32_t b, uint32_t c, uint32_t d);
    /// Appends `other` mapped by `x` (normals follow the map).
    void append(const Mesh& other, const Xform& x = {});
};

/// Axis-aligned box [lo, hi], flat shaded; each face is a grid of cells at most `cell` long
/// (0: one cell per face). Faces meeting at an edge share its vertices' exact positions.
Mesh box(const Vec3f& lo, const Vec3f& hi, float cell = 0.f);

/// One-sided planar grid: corner + s * u + t * v, s, t in [0, 1], nu x nv cells, facing
/// cross(u, v), flat shaded. Vertices are evaluated exactly as written, so an axis-aligned
/// grid keeps its constant coordinate exactly.
Mesh quad_grid(const Vec3f& corner, const Vec3f& u, const Vec3f& v, int nu, int nv);

/// Box of half-extents `half` centred at the origin whose edges and corners are rounded with
/// `radius` (0 < radius <= min half-extent), `arc` segments per quarter circle; the flat part
/// of each face is split into cells at most `cell` long (0: one cell).
Mesh rounded_box(const Vec3f& half, float radius, int arc, Shading shading = Shading::smooth,
                 float cell = 0.f);

/// rounded_box() spanning the axis-aligned block [lo, hi].
Mesh rounded_block(const Vec3f& lo, const Vec3f& hi, float radius, int arc);

/// Bends a mesh in the xz plane: z -> z - k x^2; normals follow (inverse transpose of the
/// Jacobian), zero normals stay zero.
void bend(Mesh& m, float k);

/// Surface of revolution around +y. `profile` lists (radius, y) points from bottom to top
/// (outside surface traversed upward, so normals point away from the axis); a radius of 0
/// closes the surface at the axis, and a repeated point makes a crease (no smoothing across).
Mesh lathe(std::span<const Vec2f> profile, int segments, Shading shading = Shading::smooth);

/// Truncated cone (cylinder when r_bottom == r_top) from y = 0 to y = height, with optional
/// flat caps.
Mesh cylinder(float r_bottom, float r_top, float height, int segments, bool cap_bottom = true,
              bool cap_top = true);

/// Sphere of radius r centred at the origin, smooth shaded.
Mesh sphere(float r, int segments, int rings);

/// Torus around +y in the xz plane: ring radius `major`, tube radius `minor`.
Mesh torus(float major, float minor, int segments, int sides);

/// Tube swept along `path` (at least 2 points) with one radius per path point, `sides` around,
/// frames by parallel transport; `caps` closes both ends with flat fans.
Mesh tube(std::span<const Vec3f> path, std::span<const float> radii, int sides, bool caps);

/// A path through `corners` whose inner corners are rounded: each corner is replaced by a
/// quadratic Bezier arc of `steps` segments starting `radius` before it (less when the legs are
/// short). Feed it to tube() for bent tubes.
std::vector<Vec3f> rounded_polyline(std::span<const Vec3f> corners, float radius, int steps);

/// Prism over a simple polygon in the xy plane (counter-clockwise), from z = 0 to z = depth,
/// flat shaded; caps are triangulated by ear clipping.
Mesh extrude(std::span<const Vec2f> polygon, float depth);

/// A leaf: base at the origin, midrib along +y of length `length`, blade in the xy plane of
/// largest width `width`, folded along the midrib by `fold` (edge z offset relative to the
/// half width) and drooping by `droop` (tip at z = -droop * length); `segments` >= 2 along the
/// length, 4 (segments - 1) triangles, two-sided (flat shaded).
Mesh leaf(float length, float width, float fold, float droop, int segments);

/// Deterministic random numbers: a fixed std::mt19937, floats built from its 32-bit outputs.
class SceneRng {
public:
    explicit SceneRng(uint32_t seed) : gen_(seed) {}
    /// Uniform in [0, 1): the top 24 bits of one output, times 2^-24.
    float uniform() { return float(gen_() >> 8) * 0x1p-24f; }
    /// Uniform in [lo, hi).
    float range(float lo, float hi) { return lo + (hi - lo) * uniform(); }
    /// Uniform integer in [0, n).
    uint32_t below(uint32_t n) { return uint32_t((uint64_t(gen_()) * n) >> 32); }

private:
    std::mt19937 gen_;
};

/// Collects meshes per material and writes them into a Scene in material order, so a scene of
/// many small parts becomes one add_mesh call per material.
/// A Phong material (diffuse, specular, exponent, mirror reflectivity) named `name`.
Material phong(const char* name, Vec3f diffuse, Vec3f specular = Vec3f{0.f}, float shininess = 32.f,
               float mirror = 0.f);

class SceneBuilder {
public:
    explicit SceneBuilder(Scene& scene) : scene_(scene) {}
    /// Adds a material; returns its index.
    uint32_t material(const Material& m);
    /// Queues `mesh` mapped by `x` for material `mat`.
    void add(uint32_t mat, const Mesh& mesh, const Xform& x = {});
    /// Moves everything queued into the scene (call once, at the end).
    void finish();

private:
    Scene& scene_;
    std::vector<Mesh> per_material_;
};

}  // namespace rtt::proc
