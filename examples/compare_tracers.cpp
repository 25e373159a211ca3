// RTT against 4-wide packets on the same camera rays: every answer must be the same, bit for
// bit; the times show what RTT saves. With antialiasing (argument K, default 4) a 4x4-pixel
// tile holds 16 K^2 rays answered from one shaft.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <vector>

#include <rtt/camera.h>
#include <rtt/kdtree.h>
#include <rtt/rtt_options.h>
#include <rtt/tracer.h>

namespace {

/// A wavy terrain of n x n quads: coherent, mostly planar-per-triangle geometry.
rtt::Scene terrain(int n) {
    std::vector<rtt::Vec3f> v;
    std::vector<rtt::TriangleIndices> t;
    for (int z = 0; z <= n; ++z)
        for (int x = 0; x <= n; ++x) {
            const float fx = float(x) / float(n) * 20.f - 10.f, fz = float(z) / float(n) * 20.f - 10.f;
            v.push_back({fx, 0.3f * std::sin(fx) * std::cos(0.7f * fz), fz});
        }
    const auto at = [n](int x, int z) { return uint32_t(z * (n + 1) + x); };
    for (int z = 0; z < n; ++z)
        for (int x = 0; x < n; ++x) {
            t.push_back({at(x, z), at(x, z + 1), at(x + 1, z + 1)});
            t.push_back({at(x, z), at(x + 1, z + 1), at(x + 1, z)});
        }
    return rtt::Scene::from_mesh(v, t, "terrain");
}

/// Traces every 4x4-pixel tile of the image; returns the seconds spent inside the tracer.
double trace_image(const rtt::Tracer& tracer, const rtt::CameraRays& camera,
                   std::vector<rtt::Hit>& hits) {
    const int side = 4 * camera.aa(), per_tile = side * side;
    const int tiles_x = camera.width() / 4, tiles_y = camera.height() / 4;
    hits.assign(size_t(tiles_x) * size_t(tiles_y) * size_t(per_tile), rtt::Hit{});
    std::vector<rtt::Ray> rays(static_cast<size_t>(per_tile));
    double seconds = 0;
    for (int ty = 0; ty < tiles_y; ++ty)
        for (int tx = 0; tx < tiles_x; ++tx) {
            camera.tile_rays(tx, ty, rays);
            const auto start = std::chrono::steady_clock::now();
            tracer.intersect(rtt::RayTile{side, side, rays, true},
                             std::span(hits).subspan(size_t(ty * tiles_x + tx) * size_t(per_tile),
                                                     size_t(per_tile)));
            seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        }
    return seconds;
}

}  // namespace

int main(int argc, char** argv) {
    const int aa = argc > 1 ? std::atoi(argv[1]) : 4;
    if (aa < 1 || aa > 16) {
        std::fprintf(stderr, "compare_tracers: K must be 1..16\n");
        return 2;
    }
    const rtt::Scene scene = terrain(200);
    const rtt::KdTree tree = rtt::build_kdtree(scene);
    const rtt::Camera camera{{0, 4, 12}, {0, 0, 0}, {0, 1, 0}, 50.f};
    const rtt::CameraRays rays(camera, 320, 240, aa);

    std::vector<rtt::Hit> packet_hits, rtt_hits;
    const double packet_s = trace_image(*rtt::make_tracer("packet", scene, tree), rays, packet_hits);
    // RTT with its options typed (rtt/rtt_options.h); make_tracer("rtt", ...) gives the defaults.
    rtt::RttOptions options;
    options.walk_budget_base = 64;  // let the shaft walk enter a few more nodes before giving up
    const double rtt_s = trace_image(*rtt::make_rtt_tracer(scene, tree, options), rays, rtt_hits);

    size_t mismatches = 0;
    for (size_t i = 0; i < rtt_hits.size(); ++i) mismatches += !(rtt_hits[i] == packet_hits[i]);
    std::printf("%zu triangles, 320x240 with %dx%d samples: %zu rays\n", scene.triangle_count(), aa,
                aa, rtt_hits.size());
    std::printf("packet %.3f s, rtt %.3f s, rtt/packet %.2fx, %zu mismatches\n", packet_s, rtt_s,
                packet_s / rtt_s, mismatches);
    return mismatches == 0 ? 0 : 1;
}
