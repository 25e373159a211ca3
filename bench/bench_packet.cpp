// The packet tracers against the single-ray reference on exactly the same tiles: a bumpy
// tessellated sphere (~130k triangles) on a terrain grid, 1024x768, one sample per pixel,
// 4x4-pixel tiles, one thread. Primary rays, then shadow segments from the primary hits to one
// point light (every tracer gets the same segments). After the runs, a table of median CPU times
// and speed-ups over "ray".
//
//   bench_packet [--help] [--sphere=RINGSxSEGMENTS] [Google Benchmark flags, e.g.
//                 --benchmark_repetitions=5 --benchmark_filter=Primary]
//
// --sphere sets the sphere's tessellation (default 250x256: 128,000 triangles; 20x20 makes
// triangles much larger than the pixels, to see how packet speed-ups depend on coherence).
//
// Counters: Mrays = million rays (shadow: active segments) per CPU second; for "packet",
// from one extra counted frame: nodes/ray = inner-node visits by packets per ray,
// ray_nodes/ray = the same rays' own inner-node visits (what single rays do), lanes/node =
// active lanes per visited node, tests/ray = K-wide triangle tests per ray, single = rays
// traced alone after an octant split.
#include <benchmark/benchmark.h>
#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "kd_bench_meshes.h"
#include "rtt/camera.h"
#include "rtt/kdtree.h"
#include "rtt/tracer.h"
#include "simd/simd.h"
#include "trace/trace_packet.h"

namespace rtt {
namespace {

constexpr int width = 1024, height = 768, tile = 4, tile_rays = tile * tile;
int sphere_rings = 250, sphere_segments = 256;  // --sphere

/// An n x n terrain of gentle hills around y = -1.1, 10 units across.
void add_terrain(Scene& s, uint32_t mat, int n) {
    std::vector<Vec3f> v;
    std::vector<TriangleIndices> t;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const float x = -5.f + 10.f * float(i) / float(n),
                        z = -5.f + 10.f * float(j) / float(n);
            v.push_back({x, -1.1f + 0.15f * std::sin(1.7f * x) * std::cos(1.3f * z), z});
        }
    const auto at = [&](int i, int j) { return uint32_t(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            t.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            t.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    s.add_mesh(v, t, mat);
}

/// The scene, the tree and the tiles every tracer answers.
struct Workload {
    Scene scene;
    KdTree tree;
    std::vector<Ray> rays;        ///< Tile after tile, 16 rays each (row-major inside a tile).
    std::vector<Vec3f> points;    ///< Hit point of each ray (reference tracer).
    std::vector<uint32_t> ids;    ///< Triangle each ray hit.
    std::vector<uint8_t> active;  ///< 1 when the ray hit something.
    std::vector<Hit> ref_hits;
    std::vector<uint8_t> ref_visible;
    Vec3f light{2.5f, 4.f, 1.5f};
    size_t hit_count = 0;
};

const Workload& workload() {
    static const Workload w = [] {
        Workload w;
        const uint32_t mat = w.scene.add_material({});
        kdbench::add_bumpy_sphere(w.scene, mat, sphere_rings,
                                  sphere_segments);  // 128,000 triangles by default
        add_terrain(w.scene, mat, 64);               //   8,192 triangles
        w.tree = build_kdtree(w.scene);
        const Camera cam{{2.4f, 1.0f, 2.8f}, {0.f, -0.25f, 0.f}, {0.f, 1.f, 0.f}, 50.f};
        const CameraRays camera(cam, width, height, 1);
        for (int ty = 0; ty < height; ty += tile)
            for (int tx = 0; tx < width; tx += tile)
                for (int y = 0; y < tile; ++y)
                    for (int x = 0; x < tile; ++x)
                        w.rays.push_back(
                            Ray{camera.origin(), camera.direction(tx + x, ty + y, 0, 0)});
        const std::unique_ptr<Tracer> ref = make_tracer("ray", w.scene, w.tree);
        w.ref_hits.resize(w.rays.size());
        for (size_t i = 0; i < w.rays.size(); i += tile_rays)
            ref->intersect(RayTile{tile, tile, std::span(w.rays).subspan(i, tile_rays), true},
                           std::span(w.ref_hits).subspan(i, tile_rays));
        for (size_t i = 0; i < w.rays.size(); ++i) {
            const Hit& h = w.ref_hits[i];
            w.points.push_back(w.rays[i].org + h.t * w.rays[i].dir);
            w.ids.push_back(h.tri);
            w.active.push_back(h.valid());
            w.hit_count += h.valid();
        }
        w.ref_visible.resize(w.rays.size());
        for (size_t i = 0; i < w.rays.size(); i += tile_rays)
            ref->occluded(
                SegmentTile{tile, tile, w.light, std::span(w.points).subspan(i, tile_rays),
                            std::span(w.ids).subspan(i, tile_rays),
                            std::span(w.active).subspan(i, tile_rays), true},
                std::span(w.ref_visible).subspan(i, tile_rays));
        return w;
    }();
    return w;
}

void trace_frame(const Tracer& tracer, const Workload& w, std::span<Hit> hits) {
    for (size_t i = 0; i < w.rays.size(); i += tile_rays)
        tracer.intersect(RayTile{tile, tile, std::span(w.rays).subspan(i, tile_rays), true},
                         hits.subspan(i, tile_rays));
}

void shadow_frame(const Tracer& tracer, const Workload& w, std::span<uint8_t> visible) {
    for (size_t i = 0; i < w.rays.size(); i += tile_rays)
        tracer.occluded(SegmentTile{tile, tile, w.light, std::span(w.points).subspan(i, tile_rays),
                                    std::span(w.ids).subspan(i, tile_rays),
                                    std::span(w.active).subspan(i, tile_rays), true},
                        visible.subspan(i, tile_rays));
}

/// Traversal counters of one frame traced with packets of K (primary or shadow).
template <int K>
PacketStats frame_stats(const Workload& w, bool shadows) {
    const TriangleArray tris = gather_triangles(w.scene);
    std::vector<Hit> hits(tile_rays);
    std::vector<uint8_t> visible(tile_rays);
    PacketStats st;
    for (size_t i = 0; i < w.rays.size(); i += tile_rays) {
        if (shadows)
            occluded_tile_packets<K>(
                w.tree, tris,
                SegmentTile{tile, tile, w.light, std::span(w.points).subspan(i, tile_rays),
                            std::span(w.ids).subspan(i, tile_rays),
                            std::span(w.active).subspan(i, tile_rays), true},
                visible, &st);
        else
            trace_tile_packets<K>(
                w.tree, tris, RayTile{tile, tile, std::span(w.rays).subspan(i, tile_rays), true},
                hits, &st);
    }
    return st;
}

/// Counters of "packet": inner-node visits per ray by the packets and by the same rays
/// alone (each lane's own path), lanes active per visited node, triangle tests per ray.
void add_packet_counters(benchmark::State& state, const std::string& kind, const Workload& w,
                         bool shadows) {
    PacketStats st;
    // This file is compiled at the SSE4.2 baseline: the wider kernels are reached only through
    // make_tracer (src/simd/isa.h), so their counters are not taken here.
    if (kind == "packet") st = frame_stats<4>(w, shadows);
    if (st.lanes == 0) return;
    const double lanes = double(st.lanes);
    state.counters["nodes/ray"] = double(st.inner) / lanes;
    state.counters["ray_nodes/ray"] = double(st.inner_lanes) / lanes;
    state.counters["lanes/node"] = double(st.inner_lanes) / double(st.inner);
    state.counters["tests/ray"] = double(st.tests) / lanes;
    state.counters["single"] = double(st.single_rays);
}

void primary(benchmark::State& state, const std::string& kind) {
    const Workload& w = workload();
    const std::unique_ptr<Tracer> tracer = make_tracer(kind, w.scene, w.tree);
    std::vector<Hit> hits(w.rays.size());
    for (auto _ : state) {
        trace_frame(*tracer, w, hits);
        benchmark::DoNotOptimize(hits.data());
    }
    size_t mismatches = 0;
    for (size_t i = 0; i < hits.size(); ++i) mismatches += !(hits[i] == w.ref_hits[i]);
    state.counters["mismatches"] = double(mismatches);
    add_packet_counters(state, kind, w, false);
    state.counters["Mrays"] = benchmark::Counter(double(w.rays.size()) * 1e-6,
                                                 benchmark::Counter::kIsIterationInvariantRate);
}

void shadow(benchmark::State& state, const std::string& kind) {
    const Workload& w = workload();
    const std::unique_ptr<Tracer> tracer = make_tracer(kind, w.scene, w.tree);
    std::vector<uint8_t> visible(w.rays.size());
    for (auto _ : state) {
        shadow_frame(*tracer, w, visible);
        benchmark::DoNotOptimize(visible.data());
    }
    size_t mismatches = 0;
    for (size_t i = 0; i < visible.size(); ++i) mismatches += visible[i] != w.ref_visible[i];
    state.counters["mismatches"] = double(mismatches);
    add_packet_counters(state, kind, w, true);
    state.counters["Mrays"] = benchmark::Counter(double(w.hit_count) * 1e-6,
                                                 benchmark::Counter::kIsIterationInvariantRate);
}

/// Console output as usual, plus a table of median CPU times (the machine may be shared, so
/// CPU time, not wall time) and speed-ups over "ray" at the end.
class RatioReporter : public benchmark::ConsoleReporter {
public:
    void ReportRuns(const std::vector<Run>& runs) override {
        ConsoleReporter::ReportRuns(runs);
        for (const Run& r : runs) {
            if (r.run_type == Run::RT_Aggregate && r.aggregate_name != "median") continue;
            const std::string name = r.run_name.function_name;
            if (!times_.count(name)) order_.push_back(name);
            times_[name].push_back(r.GetAdjustedCPUTime());
        }
    }
    void Finalize() override {
        ConsoleReporter::Finalize();
        const Workload& w = workload();
        std::printf(
            "\n%zu triangles, %dx%d, %zu primary rays, %zu shadow segments, kd-tree %zu nodes\n",
            w.scene.triangle_count(), width, height, w.rays.size(), w.hit_count,
            w.tree.stats.nodes);
        std::printf("%-18s %12s %10s %10s\n", "benchmark", "CPU ms", "Mrays/s", "vs ray");
        for (const char* what : {"Primary/", "Shadow/"}) {
            const double base = median(std::string(what) + "ray");
            const double rays =
                double(std::string(what) == "Primary/" ? w.rays.size() : w.hit_count);
            for (const std::string& name : order_) {
                if (name.rfind(what, 0) != 0) continue;
                const double ms = median(name);
                std::printf("%-18s %12.2f %10.2f %9.2fx\n", name.c_str(), ms, rays / (ms * 1e3),
                            base > 0 ? base / ms : 0.);
            }
        }
    }

private:
    double median(const std::string& name) {
        auto it = times_.find(name);
        if (it == times_.end()) return 0.;
        std::vector<double> t = it->second;
        std::sort(t.begin(), t.end());
        return t[t.size() / 2];
    }
    std::map<std::string, std::vector<double>> times_;
    std::vector<std::string> order_;
};

}  // namespace
}  // namespace rtt

int main(int argc, char** argv) {
    std::vector<char*> args;
    for (int i = 0; i < argc; ++i) {
        if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
            std::printf(
                "bench_packet: ray vs packet vs packet8 vs packet16 (those this build has), "
                "primary rays\n"
                "and shadow segments of a ~136k-triangle bumpy sphere on a terrain, 1024x768, 1 "
                "thread.\n"
                "  --sphere=RxS  sphere tessellation, R rings x S segments (default 250x256)\n"
                "Prints Google Benchmark's table (Mrays = million rays per CPU second, mismatches "
                "against\n"
                "the reference tracer, must be 0), then median CPU times and speed-ups over "
                "'ray'.\n");
            return 0;
        }
        if (std::strncmp(argv[i], "--sphere=", 9) == 0) {
            if (std::sscanf(argv[i] + 9, "%dx%d", &rtt::sphere_rings, &rtt::sphere_segments) != 2 ||
                rtt::sphere_rings < 2 || rtt::sphere_segments < 3) {
                std::fprintf(stderr, "bench_packet: --sphere wants RINGSxSEGMENTS, e.g. 250x256\n");
                return 1;
            }
            continue;
        }
        args.push_back(argv[i]);
    }
    argc = int(args.size());
    argv = args.data();
    // One thread: the tracers run on the calling thread; this also keeps the build serial.
    const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    for (const char* what : {"Primary/", "Shadow/"})
        for (const std::string& kind : rtt::tracer_kinds()) {
            if (kind != "ray" && !kind.starts_with("packet")) continue;
            benchmark::RegisterBenchmark((what + kind).c_str(),
                                         what[0] == 'P' ? rtt::primary : rtt::shadow, kind)
                ->Unit(benchmark::kMillisecond);
        }
    rtt::RatioReporter reporter;
    benchmark::RunSpecifiedBenchmarks(&reporter);
    benchmark::Shutdown();
    return 0;
}
