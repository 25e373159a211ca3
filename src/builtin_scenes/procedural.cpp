// Mesh container, transforms, flat primitives (boxes, grids, extrusions) and the scene
// builder. Curved primitives are in procedural_curved.cpp.
#include "builtin_scenes/procedural.h"

#include <cmath>
#include <utility>

#include "core/check.h"

namespace rtt::proc {

Vec3f Xform::normal(const Vec3f& n) const {
    if (n == Vec3f{0.f}) return n;
    // Cofactor matrix: det(M) * M^-T, whose columns are the pairwise cross products.
    Vec3f m = cross(c1, c2) * n.x + cross(c2, c0) * n.y + cross(c0, c1) * n.z;
    if (dot(c0, cross(c1, c2)) < 0.f) m = -m;
    return normalize(m);
}

Xform Xform::operator*(const Xform& in) const {
    Xform r;
    r.c0 = vector(in.c0);
    r.c1 = vector(in.c1);
    r.c2 = vector(in.c2);
    r.t = point(in.t);
    return r;
}

Xform Xform::translate(const Vec3f& d) {
    Xform r;
    r.t = d;
    return r;
}

Xform Xform::scale(const Vec3f& s) {
    Xform r;
    r.c0 = {s.x, 0.f, 0.f};
    r.c1 = {0.f, s.y, 0.f};
    r.c2 = {0.f, 0.f, s.z};
    return r;
}

Xform Xform::rotate_x(float a) {
    const float c = std::cos(a), s = std::sin(a);
    Xform r;
    r.c1 = {0.f, c, s};
    r.c2 = {0.f, -s, c};
    return r;
}

Xform Xform::rotate_y(float a) {
    const float c = std::cos(a), s = std::sin(a);
    Xform r;
    r.c0 = {c, 0.f, -s};
    r.c2 = {s, 0.f, c};
    return r;
}

Xform Xform::rotate_z(float a) {
    const float c = std::cos(a), s = std::sin(a);
    Xform r;
    r.c0 = {c, s, 0.f};
    r.c1 = {-s, c, 0.f};
    return r;
}

Xform Xform::basis(const Vec3f& x, const Vec3f& y, const Vec3f& z, const Vec3f& origin) {
    Xform r;
    r.c0 = x;
    r.c1 = y;
    r.c2 = z;
    r.t = origin;
    return r;
}

uint32_t Mesh::add_vertex(const Vec3f& p, const Vec3f& n) {
    vertices.push_back(p);
    normals.push_back(n);
    return uint32_t(vertices.size() - 1);
}

void Mesh::add_quad(uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
    add_triangle(a, b, c);
    add_triangle(a, c, d);
}

void Mesh::append(const Mesh& other, const Xform& x) {
    const auto base = uint32_t(vertices.size());
    // A reflecting map turns counter-clockwise into clockwise: swap two corners to keep
    // triangles facing outward.
    const bool mirrored = dot(x.c0, cross(x.c1, x.c2)) < 0.f;
    for (size_t i = 0; i < other.vertices.size(); ++i) {
        vertices.push_back(x.point(other.vertices[i]));
        normals.push_back(x.normal(other.normals[i]));
    }
    for (const TriangleIndices& t : other.triangles) {
        if (mirrored)
            triangles.push_back({t[0] + base, t[2] + base, t[1] + base});
        else
            triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
}

namespace {

/// n + 1 coordinates from lo to hi whose ends are exactly lo and hi, so faces that meet at an
/// edge compute identical vertices there.
std::vector<float> axis_coords(float lo, float hi, int n) {
    std::vector<float> c(size_t(n) + 1);
    for (int i = 0; i <= n; ++i) c[size_t(i)] = lo + (hi - lo) * (float(i) / float(n));
    c[size_t(n)] = hi;
    return c;
}

int cells(float length, float cell) {
    if (cell <= 0.f) return 1;
    return std::max(1, int(std::ceil(length / cell - 1e-4f)));
}

/// One face of a box-like grid: axis `a` fixed at coords[a].front() or .back() (positive), the
/// other two axes ordered so that cross(u, v) points outward. `map` turns a grid point into a
/// (position, normal) pair.
template <typename Map>
void grid_face(Mesh& m, const std::vector<float> (&coords)[3], int a, bool positive, Map map) {
    const int u = positive ? (a + 1) % 3 : (a + 2) % 3;
    const int v = positive ? (a + 2) % 3 : (a + 1) % 3;
    const float fixed = positive ? coords[a].back() : coords[a].front();
    const size_t nu = coords[u].size(), nv = coords[v].size();
    const auto base = uint32_t(m.vertices.size());
    for (size_t i = 0; i < nu; ++i)
        for (size_t j = 0; j < nv; ++j) {
            Vec3f p;
            p[a] = fixed;
            p[u] = coords[u][i];
            p[v] = coords[v][j];
            auto [pos, n] = map(p);
            m.add_vertex(pos, n);
        }
    for (size_t i = 0; i + 1 < nu; ++i)
        for (size_t j = 0; j + 1 < nv; ++j) {
            const auto a00 = base + uint32_t(i * nv + j);
            const auto a10 = a00 + uint32_t(nv);
            m.add_quad(a00, a10, a10 + 1, a00 + 1);
        }
}

}  // namespace

Mesh box(const Vec3f& lo, const Vec3f& hi, float cell) {
    const Vec3f d = hi - lo;
    const std::vector<float> coords[3] = {axis_coords(lo.x, hi.x, cells(d.x, cell)),
                                          axis_coords(lo.y, hi.y, cells(d.y, cell)),
                                          axis_coords(lo.z, hi.z, cells(d.z, cell))};
    Mesh m;
    auto identity = [](const Vec3f& p) { return std::pair{p, Vec3f{0.f}}; };
    for (int a = 0; a < 3; ++a) {
        grid_face(m, coords, a, false, identity);
        grid_face(m, coords, a, true, identity);
    }
    return m;
}

Mesh quad_grid(const Vec3f& corner, const Vec3f& u, const Vec3f& v, int nu, int nv) {
    RTT_CHECK(nu >= 1 && nv >= 1);
    Mesh m;
    for (int i = 0; i <= nu; ++i)
        for (int j = 0; j <= nv; ++j)
            m.add_vertex(corner + u * (float(i) / float(nu)) + v * (float(j) / float(nv)));
    const auto stride = uint32_t(nv + 1);
    for (uint32_t i = 0; i < uint32_t(nu); ++i)
        for (uint32_t j = 0; j < uint32_t(nv); ++j) {
            const uint32_t a = i * stride + j;
            m.add_quad(a, a + stride, a + stride + 1, a + 1);
        }
    return m;
}

Mesh rounded_box(const Vec3f& half, float radius, int arc, Shading shading, float cell) {
    RTT_CHECK(radius > 0.f && arc >= 1);
    RTT_CHECK(radius <= half.x && radius <= half.y && radius <= half.z);
    // Each face of a cube is gridded so that, after pulling every point onto the rounded
    // surface (inner box + radius * direction from the nearest inner-box point), the edge
    // region of a face samples its 45 degrees of the quarter circle uniformly: a face point at
    // (h - r) + r tan(theta) lands at angle theta.
    std::vector<float> coords[3];
    Vec3f inner;
    for (int a = 0; a < 3; ++a) {
        const float h = half[a];
        inner[a] = h - radius;
        std::vector<float> pos;
        for (int k = 1; k <= arc; ++k)
            pos.push_back(inner[a] + radius * std::tan(radians(45.f) * float(k) / float(arc)));
        std::vector<float>& c = coords[a];
        for (int k = arc - 1; k >= 0; --k) c.push_back(-pos[size_t(k)]);
        if (inner[a] > 0.f) {
            const std::vector<float> mid =
                axis_coords(-inner[a], inner[a], cells(2.f * inner[a], cell));
            c.insert(c.end(), mid.begin(), mid.end());
        } else {
            c.push_back(-inner[a]);
        }
        for (float p : pos) c.push_back(p);
    }
    const bool smooth = shading == Shading::smooth;
    auto map = [&](const Vec3f& p) {
        const Vec3f core = min(max(p, -inner), inner);
        const Vec3f n = normalize(p - core);
        return std::pair{core + n * radius, smooth ? n : Vec3f{0.f}};
    };
    Mesh m;
    for (int a = 0; a < 3; ++a) {
        grid_face(m, coords, a, false, map);
        grid_face(m, coords, a, true, map);
    }
    return m;
}

void bend(Mesh& m, float k) {
    for (size_t i = 0; i < m.vertices.size(); ++i) {
        const Vec3f p = m.vertices[i];
        m.vertices[i].z = p.z - k * p.x * p.x;
        // The map's Jacobian has -2kx in row z, column x; its inverse transpose adds 2kx n.z to
        // n.x.
        const Vec3f n = m.normals[i];
        if (!(n == Vec3f{0.f})) m.normals[i] = normalize({n.x + 2.f * k * p.x * n.z, n.y, n.z});
    }
}

namespace {

double cross2(const Vec2f& o, const Vec2f& a, const Vec2f& b) {
    return (double(a.x) - o.x) * (double(b.y) - o.y) - (double(a.y) - o.y) * (double(b.x) - o.x);
}

bool inside_triangle(const Vec2f& p, const Vec2f& a, const Vec2f& b, const Vec2f& c) {
    return cross2(a, b, p) >= 0.0 && cross2(b, c, p) >= 0.0 && cross2(c, a, p) >= 0.0;
}

/// Ear clipping of a simple counter-clockwise polygon: n - 2 triangles, counter-clockwise.
std::vector<TriangleIndices> triangulate(std::span<const Vec2f> poly) {
    std::vector<uint32_t> idx(poly.size());
    for (size_t i = 0; i < idx.size(); ++i) idx[i] = uint32_t(i);
    std::vector<TriangleIndices> out;
    while (idx.size() > 3) {
        bool clipped = false;
        for (size_t i = 0; i < idx.size() && !clipped; ++i) {
            const uint32_t ia = idx[(i + idx.size() - 1) % idx.size()], ib = idx[i],
                           ic = idx[(i + 1) % idx.size()];
            if (cross2(poly[ia], poly[ib], poly[ic]) <= 0.0) continue;  // reflex corner
            bool empty = true;
            for (uint32_t j : idx)
                if (j != ia && j != ib && j != ic &&
                    inside_triangle(poly[j], poly[ia], poly[ib], poly[ic]))
                    empty = false;
            if (!empty) continue;
            out.push_back({ia, ib, ic});
            idx.erase(idx.begin() + std::ptrdiff_t(i));
            clipped = true;
        }
        RTT_CHECK(clipped);  // a simple counter-clockwise polygon always has an ear
    }
    out.push_back({idx[0], idx[1], idx[2]});
    return out;
}

}  // namespace

Mesh extrude(std::span<const Vec2f> polygon, float depth) {
    RTT_CHECK(polygon.size() >= 3);
    Mesh m;
    const auto n = uint32_t(polygon.size());
    for (const Vec2f& p : polygon) m.add_vertex({p.x, p.y, 0.f});
    for (const Vec2f& p : polygon) m.add_vertex({p.x, p.y, depth});
    for (const TriangleIndices& t : triangulate(polygon)) {
        m.add_triangle(t[0], t[2], t[1]);              // bottom, facing -z
        m.add_triangle(t[0] + n, t[1] + n, t[2] + n);  // top, facing +z
    }
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t j = (i + 1) % n;
        m.add_quad(i, j, j + n, i + n);
    }
    return m;
}

Mesh rounded_block(const Vec3f& lo, const Vec3f& hi, float radius, int arc) {
    Mesh m;
    m.append(rounded_box((hi - lo) * 0.5f, radius, arc), Xform::translate((lo + hi) * 0.5f));
    return m;
}

Material phong(const char* name, Vec3f diffuse, Vec3f specular, float shininess, float mirror) {
    Material m;
    m.name = name;
    m.diffuse = diffuse;
    m.specular = specular;
    m.shininess = shininess;
    m.mirror = mirror;
    return m;
}

uint32_t SceneBuilder::material(const Material& m) {
    const uint32_t index = scene_.add_material(m);
    per_material_.resize(size_t(index) + 1);
    return index;
}

void SceneBuilder::add(uint32_t mat, const Mesh& mesh, const Xform& x) {
    RTT_CHECK_LT(size_t(mat), per_material_.size());
    per_material_[mat].append(mesh, x);
}

void SceneBuilder::finish() {
    for (size_t i = 0; i < per_material_.size(); ++i) {
        const Mesh& m = per_material_[i];
        if (!m.triangles.empty()) scene_.add_mesh(m.vertices, m.triangles, uint32_t(i), m.normals);
    }
    per_material_.clear();
}

}  // namespace rtt::proc
