// RTT against 4-wide packets on the same camera rays: every answer must be the same, bit for
// bit; the times show what RTT saves. The image goes to the tracers as the renderer hands it
// over: regions of R x R pixels (rtt::default_region(K): 32 pixels at K = 1, 8 from K = 2 to 8),
// each tried by RTT as one shaft.
#include <rtt/camera.h>
#include <rtt/kdtree.h>
#include <rtt/render.h>
#include <rtt/rtt_options.h>
#include <rtt/tracer.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <vector>

namespace {

/// A wavy terrain of n x n quads: coherent, mostly planar-per-triangle geometry.
rtt::Scene terrain(int n) {
    std::vector<rtt::Vec3f> v;
    std::vector<rtt::TriangleIndices> t;
    for (int z = 0; z <= n; ++z)
        for (int x = 0; x <= n; ++x) {
            const float fx = float(x) / float(n) * 20.f - 10.f,
                        fz = float(z) / float(n) * 20.f - 10.f;
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

/// Traces the image region by region; returns the seconds spent inside the tracer. hits[] holds
/// each region's samples in its own grid order, regions in row-major order.
double trace_image(const rtt::Tracer& tracer, const rtt::CameraRays& camera,
                   std::vector<rtt::Hit>& hits) {
    const int k = camera.aa(), cell = 4 * k;
    const int tiles_per_region = rtt::default_region(k) / 4;
    const int tiles_x = (camera.width() + 3) / 4, tiles_y = (camera.height() + 3) / 4;
    hits.assign(size_t(tiles_x) * size_t(tiles_y) * size_t(cell * cell), rtt::Hit{});
    std::vector<rtt::Ray> rays;
    size_t done = 0;
    double seconds = 0;
    for (int ty = 0; ty < tiles_y; ty += tiles_per_region)
        for (int tx = 0; tx < tiles_x; tx += tiles_per_region) {
            const int cols = std::min(tiles_per_region, tiles_x - tx);
            const int rows = std::min(tiles_per_region, tiles_y - ty);
            rays.resize(size_t(cols * cell) * size_t(rows * cell));
            camera.region_rays(tx, ty, cols, rows, rays);
            const rtt::RayTile region{cols * cell, rows * cell, rays, true,
                                      tiles_per_region > 1 ? cell : 0};
            const auto start = std::chrono::steady_clock::now();
            tracer.intersect(region, std::span(hits).subspan(done, rays.size()));
            seconds +=
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            done += rays.size();
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
    const double packet_s =
        trace_image(*rtt::make_tracer("packet", scene, tree), rays, packet_hits);
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
