#include "geom/triangle.h"

namespace rtt {

std::vector<TriangleVerts> gather_triangles(const Scene& scene) {
    std::vector<TriangleVerts> out;
    out.reserve(scene.triangles.size());
    for (const TriangleIndices& t : scene.triangles)
        out.push_back({scene.vertices[t[0]], scene.vertices[t[1]], scene.vertices[t[2]]});
    return out;
}

}  // namespace rtt
