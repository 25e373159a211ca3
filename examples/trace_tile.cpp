// A mesh from arrays in memory, its kd-tree, and one 4x4-pixel tile of camera rays answered by
// RTT as a shaft: the smallest complete use of rtt::core.
#include <rtt/camera.h>
#include <rtt/kdtree.h>
#include <rtt/rtt_options.h>
#include <rtt/tracer.h>

#include <cstdio>
#include <vector>

int main() {
    // A floor of two triangles and a small upright quad in front of it.
    const std::vector<rtt::Vec3f> vertices = {
        {-4, 0, -4}, {4, 0, -4}, {4, 0, 4}, {-4, 0, 4},  // floor
        {-1, 0, 0},  {1, 0, 0},  {1, 2, 0}, {-1, 2, 0},  // quad
    };
    const std::vector<rtt::TriangleIndices> triangles = {
        {0, 2, 1},
        {0, 3, 2},
        {4, 5, 6},
        {4, 6, 7},
    };
    const rtt::Scene scene = rtt::Scene::from_mesh(vertices, triangles);
    const rtt::KdTree tree = rtt::build_kdtree(scene);
    const auto tracer = rtt::make_tracer("rtt", scene, tree);

    // Tile (8, 6) of a 64x48 image, in the middle: 16 rays from one apex, so the tile is a shaft.
    const rtt::Camera camera{{0, 1, 6}, {0, 1, 0}, {0, 1, 0}, 45.f};
    const rtt::CameraRays rays_of(camera, 64, 48, 1);
    std::vector<rtt::Ray> rays(16);
    rays_of.tile_rays(8, 6, rays);
    std::vector<rtt::Hit> hits(rays.size());
    // Counters are optional: every tracer's in TraceStats, RTT's own in RttStats.
    rtt::TraceStats stats;
    rtt::RttStats rtt_stats;
    tracer->intersect(rtt::RayTile{4, 4, rays, true}, hits, {&stats, &rtt_stats});

    for (int y = 0; y < 4; ++y) {
        for (int x = 0; x < 4; ++x) {
            const rtt::Hit& h = hits[size_t(y * 4 + x)];
            if (h.valid())
                std::printf(" tri %u t %6.3f |", h.tri, double(h.t));
            else
                std::printf("      miss      |");
        }
        std::printf("\n");
    }
    std::printf("%llu rays: %llu traced, %llu answered from a relevant list of %llu triangles\n",
                (unsigned long long)stats.rays, (unsigned long long)stats.traced,
                (unsigned long long)rtt_stats.answered, (unsigned long long)rtt_stats.relevant_sum);
    // Every ray of this tile sees the quad (triangles 2 and 3).
    for (const rtt::Hit& h : hits)
        if (h.tri != 2 && h.tri != 3) return 1;
    return 0;
}
