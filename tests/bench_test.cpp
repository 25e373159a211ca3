// The benchmark harness on a tiny scene: the rays it times are the renderer's rays, every
// tracer is checked against the baseline, counts add up, JSON and SVG are well formed.
// No timing assertions: only that the numbers a benchmark prints are the right ones.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>

#include "builtin_scenes/procedural.h"
#include "experiments/experiments.h"
#include "experiments/machine_info.h"
#include "experiments/measure.h"
#include "experiments/plot_svg.h"
#include "experiments/report.h"
#include "experiments/results_doc.h"
#include "experiments/workload.h"
#include "rtt/error.h"
#include "rtt/render.h"

namespace rtt::bench {
namespace {

/// A floor of coplanar triangles (RTT shadow tiles), a box and a sphere (silhouettes), one omni
/// light and one spot light (the active rule's two cases), seen from above at an angle.
BenchScene tiny_scene() {
    BenchScene s;
    s.name = "tiny";
    const uint32_t mat = s.scene.add_material({});
    const proc::Mesh floor =
        proc::quad_grid({-2.f, 0.f, 2.f}, {4.f, 0.f, 0.f}, {0.f, 0.f, -4.f}, 6, 6);
    s.scene.add_mesh(floor.vertices, floor.triangles, mat);
    const proc::Mesh box = proc::box({-1.2f, 0.f, -0.6f}, {-0.4f, 0.9f, 0.3f});
    s.scene.add_mesh(box.vertices, box.triangles, mat);
    const proc::Mesh ball = proc::sphere(0.5f, 24, 12);
    std::vector<Vec3f> moved = ball.vertices;
    for (Vec3f& v : moved) v += Vec3f{0.7f, 0.5f, 0.2f};
    s.scene.add_mesh(moved, ball.triangles, mat);
    Light omni;
    omni.position = {0.3f, 2.5f, 1.0f};
    s.scene.lights.push_back(omni);
    Light spot;
    spot.kind = LightKind::spot;
    spot.position = {-1.5f, 2.f, -1.5f};
    spot.direction = {0.6f, -1.f, 0.6f};
    spot.outer_angle_deg = 35.f;
    spot.inner_angle_deg = 20.f;
    s.scene.lights.push_back(spot);
    s.camera = Camera{{0.5f, 2.2f, 3.2f}, {0.f, 0.2f, 0.f}, {0.f, 1.f, 0.f}, 50.f};
    s.scene.camera = s.camera;
    s.tree = build_kdtree(s.scene);
    return s;
}

const BenchScene& scene() {
    static const BenchScene s = tiny_scene();
    return s;
}

std::vector<std::string> kinds_to_compare() {
    std::vector<std::string> kinds{"ray", "packet"};
    for (const char* k : {"packet8", "packet16", "rtt", "embree"})
        if (has_tracer(k)) kinds.push_back(k);
    return kinds;
}

TEST(BenchWorkload, RaysAndShadowSegmentsAreTheRenderers) {
    // 30x22 is not a multiple of 4 (padded tiles) and K = 2; small bands force several of them.
    const int w = 30, h = 22, k = 2;
    const auto packet = make_tracer("packet", scene().scene, scene().tree);
    RenderOptions opt;
    opt.camera = scene().camera;
    opt.width = w;
    opt.height = h;
    opt.aa = k;
    opt.max_depth = 0;  // shadow segments of primary hits only, as in the benchmark
    opt.threads = 1;
    opt.hits_buffer = true;
    // Regions of 8 (the default at K = 2), 12 and 16 pixels: cut by the padded image's edge.
    for (const int region : {0, 12, 16}) {
        SCOPED_TRACE("region " + std::to_string(region));
        opt.region = region;
        const RenderResult rendered = render(scene().scene, *packet, opt);

        const Workload workload(scene(), w, h, k, 600, region);
        ASSERT_GE(workload.band_count(), 2);
        EXPECT_EQ(workload.primary_rays(), uint64_t(8 * 6) * 64);
        uint64_t mismatches = 0, compared = 0, segments = 0, jobs = 0;
        for (int b = 0; b < workload.band_count(); ++b) {
            Band band = workload.make_band(b);
            const std::vector<Hit> hits = band.intersect(*packet);
            for (size_t t = 0; t < band.tile_count(); ++t)
                for (int sr = 0; sr < band.tile_height(t); ++sr)
                    for (int sc = 0; sc < band.tile_width(t); ++sc) {
                        const int x = int(t % size_t(band.tiles_x)) * band.pixels + sc / k;
                        const int y =
                            (band.first_tile_row + int(t / size_t(band.tiles_x))) * band.pixels +
                            sr / k;
                        if (x >= w || y >= h) continue;  // padding, cropped by the renderer
                        const size_t dst = ((size_t(y) * w + x) * k + sr % k) * k + sc % k;
                        mismatches +=
                            rendered.hits[dst] !=
                            hits[band.tile_offset(t) + size_t(sr) * band.tile_width(t) + sc].tri;
                        ++compared;
                    }
            workload.add_shadows(band, hits);
            jobs += band.shadow_jobs.size();
            for (const ShadowJob& j : band.shadow_jobs) {
                segments += j.active;
                EXPECT_GT(j.active, 0u);
                EXPECT_EQ(
                    j.active,
                    uint32_t(std::count(
                        band.masks.begin() + long(j.mask_offset),
                        band.masks.begin() + long(j.mask_offset + band.tile_size(j.tile)), 1)));
            }
        }
        EXPECT_EQ(compared, uint64_t(w) * h * k * k);
        EXPECT_EQ(mismatches, 0u);
        EXPECT_GT(segments, 0u);
        // Padding samples get segments too, as in the renderer (it traces whole tiles).
        EXPECT_EQ(segments, rendered.stats.shadow.trace.rays);
        EXPECT_EQ(jobs, rendered.stats.shadow.trace.tiles);
    }
}

TEST(BenchMeasure, EveryTracerAnswersTheSameRaysAndAgrees) {
    const Workload workload(scene(), 40, 32, 2, 1000);
    const std::vector<NamedTracer> tracers = make_tracers(scene(), kinds_to_compare());
    for (int threads : {1, 2}) {
        MeasureOptions options;
        options.repetitions = 3;
        options.threads = threads;
        const Measurement m = measure(workload, tracers, options);
        EXPECT_EQ(m.primary_rays, uint64_t(40 * 32 * 4));
        EXPECT_GT(m.shadow_rays, 0u);
        EXPECT_EQ(m.mismatches(), 0u);
        ASSERT_EQ(m.tracers.size(), tracers.size());
        for (const TracerResult& t : m.tracers) {
            SCOPED_TRACE(t.kind);
            EXPECT_EQ(t.primary.rays, m.primary_rays);
            EXPECT_EQ(t.primary.stats.rays, m.primary_rays);
            EXPECT_EQ(t.shadow.stats.rays, m.shadow_rays);
            EXPECT_EQ(t.primary.stats.traced + t.primary.rtt.answered, m.primary_rays);
            EXPECT_EQ(t.primary.reps.size(), 3u);
            EXPECT_GE(t.primary.time.wall, 0.0);
            if (t.exact) {
                EXPECT_EQ(t.primary.differences, 0u);
                EXPECT_EQ(t.shadow.differences, 0u);
            } else {
                // Embree breaks exact ties its own way: a tiny fraction at most.
                EXPECT_LE(t.primary.differences, m.primary_rays / 100);
            }
        }
        EXPECT_GE(speedup(m, "packet", "ray", false, ClockKind::wall), 0.0);
    }
}

TEST(BenchWorkload, UnknownScenesFailBeforeAnyWork) {
    EXPECT_NO_THROW(require_scene("room"));
    EXPECT_THROW(require_scene("no-such-scene"), Error);
    EXPECT_THROW(load_bench_scene("no/such/file.json"), Error);
}

TEST(BenchMeasure, RejectsAMissingBaseline) {
    const Workload workload(scene(), 8, 8, 1, 100);
    MeasureOptions options;
    options.baseline = "packet";
    EXPECT_THROW(measure(workload, make_tracers(scene(), {"ray"}), options), Error);
}

/// An experiment of one measurement of `kinds` on a 16x12 image with K x K samples.
ExperimentResult tiny_experiment(int aa, const std::vector<std::string>& kinds, int repetitions) {
    const Workload workload(scene(), 16, 12, aa, 1000);
    ExperimentResult e;
    e.id = "tiny";
    e.title = "a tiny experiment";
    MeasureOptions options;
    options.repetitions = repetitions;
    e.measurements.push_back(measure(workload, make_tracers(scene(), kinds), options));
    return e;
}

TEST(BenchReport, JsonHoldsEveryFigureAndParses) {
    ExperimentResult e = tiny_experiment(1, {"ray", "packet"}, 1);
    e.tables.push_back(TextTable{"t", {"a", "b"}, {{"1", "2"}}, {"note"}});
    ResultsDocument doc;
    doc.machine = machine_info();
    doc.command = "test";
    doc.experiments.push_back(e);
    const nlohmann::json j = nlohmann::json::parse(results_json(doc).dump());
    EXPECT_FALSE(j.at("machine").at("cpu_model").get<std::string>().empty());
    EXPECT_FALSE(j.at("machine").at("git_commit").get<std::string>().empty());
    const nlohmann::json& m = j.at("experiments").at(0).at("measurements").at(0);
    EXPECT_EQ(m.at("primary_rays").get<uint64_t>(), 16u * 12u);
    EXPECT_EQ(m.at("mismatches").get<uint64_t>(), 0u);
    ASSERT_EQ(m.at("tracers").size(), 2u);
    EXPECT_EQ(m.at("tracers").at(1).at("kind"), "packet");
    EXPECT_EQ(m.at("tracers").at(1).at("primary").at("repetitions").size(), 1u);
    EXPECT_TRUE(m.at("tracers").at(1).at("shadow").at("time").contains("cpu_s"));
    const std::string md = results_markdown(doc, ".");
    EXPECT_NE(md.find("| a | b |"), std::string::npos);
    EXPECT_NE(md.find(doc.machine.cpu_model), std::string::npos);
}

TEST(BenchReport, ExperimentsComeBackFromTheirJsonUnchanged) {
    // A distributed `rtt bench` sends each experiment's result to rank 0 as this JSON.
    ExperimentResult e = tiny_experiment(2, {"packet", "rtt"}, 2);
    e.tables.push_back(TextTable{"t", {"a", "b"}, {{"1", "2"}, {"3", "4"}}, {"note"}});
    e.files = {"plot.svg"};
    e.findings = {"fast"};
    e.extra = {{"build_seconds", 0.25}};
    const nlohmann::json j = experiment_json(e);
    const ExperimentResult back = experiment_from_json(nlohmann::json::parse(j.dump()));
    EXPECT_EQ(experiment_json(back), j);
    EXPECT_EQ(back.measurements.at(0).tracers.at(1).primary.rtt.answered,
              e.measurements.at(0).tracers.at(1).primary.rtt.answered);
    EXPECT_THROW(experiment_from_json(nlohmann::json::parse("{\"id\": \"x\"}")),
                 nlohmann::json::exception);
}

TEST(BenchReport, CellsAndTables) {
    EXPECT_EQ(format_count(1234567), "1,234,567");
    EXPECT_EQ(format_count(12), "12");
    EXPECT_EQ(format_ratio(0.0), "-");
    EXPECT_EQ(format_ratio(1.234), "1.23x");
    EXPECT_EQ(format_ms(0.1234), "123.4");
    const TextTable t{"T", {"x", "y", "z"}, {{"a", "1", "2"}, {"b", "3"}}, {}};
    const std::string md = markdown_table(t);
    EXPECT_EQ(std::count(md.begin(), md.end(), '\n'), 6);  // title, blank, header, rule, 2 rows
    EXPECT_NE(md.find("| b | 3 |  |"), std::string::npos);
}

TEST(BenchPlot, SvgIsWellFormed) {
    LinePlot plot;
    plot.title = "speed-up <K>";
    plot.x_ticks = {0, 1, 2};
    plot.x_tick_labels = {"1x1", "2x2", "3x3"};
    plot.reference_y = 1.0;
    plot.series.push_back({"room primary", {0, 1, 2}, {1.1, 1.5, 2.0}, "#1f77b4", false, false});
    plot.series.push_back({"room shadow", {0, 1, 2}, {1.0, 1.2, 1.4}, "#1f77b4", true, false});
    plot.series.push_back({"paper", {0}, {1.22}, "#000000", false, true});
    plot.series.push_back({"paper shadow", {0}, {1.17}, "#000000", true, true});
    plot.series.push_back({"empty", {}, {}, "#000000", false, false});
    const std::string svg = render_svg(plot);
    auto count = [&](const std::string& what) {
        size_t n = 0;
        for (size_t p = svg.find(what); p != std::string::npos; p = svg.find(what, p + 1)) ++n;
        return n;
    };
    EXPECT_EQ(svg.rfind("<svg", 0), 0u);
    EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
    EXPECT_EQ(count("<polyline"), 2u);
    EXPECT_EQ(count("<circle"), 3u + 3u + 1u + 1u);  // points + the circle legend
    EXPECT_EQ(count("<rect x="), 1u + 1u + 1u);      // plot frame + square marker + its legend
    EXPECT_NE(svg.find("speed-up &lt;K&gt;"), std::string::npos);
    EXPECT_EQ(svg.find("nan"), std::string::npos);
}

TEST(BenchMachine, DescribesTheMachine) {
    const MachineInfo m = machine_info();
    EXPECT_FALSE(m.cpu_model.empty());
    EXPECT_TRUE(m.isa == "sse4.2" || m.isa == "avx2" || m.isa == "avx512");
    EXPECT_GE(m.simd_width, 4);
    EXPECT_FALSE(m.compiler.empty());
    EXPECT_EQ(m.date.size(), std::string("2026-01-01T00:00:00+0000").size());
}

/// Runs `rtt bench ARGS` in a fresh folder; returns the exit status and that folder.
int run_bench_cli(const std::string& args, const std::filesystem::path& dir) {
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const std::string cmd = "cd '" + dir.string() + "' && '" + std::string(RTT_CLI_PATH) +
                            "' bench " + args + " >out.txt 2>err.txt";
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

std::string read_file(const std::filesystem::path& path) {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(BenchCli, QuickExperimentsOnASceneFileWriteJsonAndPlots) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("rtt_bench_cli_" + std::to_string(getpid()));
    const std::string scene = std::string(RTT_TEST_DATA_DIR) + "/../../scenes/example.json";
    ASSERT_EQ(run_bench_cli("table1 --quick --scenes '" + scene + "' --json r.json", dir), 0)
        << read_file(dir / "err.txt");
    const nlohmann::json j = nlohmann::json::parse(read_file(dir / "r.json"));
    EXPECT_EQ(j.at("mode"), "quick");
    const nlohmann::json& m = j.at("experiments").at(0).at("measurements").at(0);
    EXPECT_EQ(m.at("primary_rays").get<uint64_t>(), 160u * 120u);
    EXPECT_GT(m.at("shadow_rays").get<uint64_t>(), 0u);
    EXPECT_EQ(m.at("mismatches").get<uint64_t>(), 0u);
    EXPECT_NE(read_file(dir / "out.txt").find("speed-up rtt/packet primary"), std::string::npos);

    ASSERT_EQ(run_bench_cli("fig7 --quick --scenes '" + scene + "' --out-dir plots", dir), 0)
        << read_file(dir / "err.txt");
    if (has_tracer("rtt")) {
        const std::string svg = read_file(dir / "plots" / "fig7_antialiasing.svg");
        EXPECT_EQ(svg.rfind("<svg", 0), 0u);
    }
    std::filesystem::remove_all(dir);
}

TEST(BenchCli, BuildTableTimesBothBuildsAndDescribesTheTree) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("rtt_bench_build_" + std::to_string(getpid()));
    const std::string scene = std::string(RTT_TEST_DATA_DIR) + "/../../scenes/example.json";
    ASSERT_EQ(run_bench_cli("build --quick --scenes '" + scene + "' --json b.json", dir), 0)
        << read_file(dir / "err.txt");
    const nlohmann::json j = nlohmann::json::parse(read_file(dir / "b.json"));
    const nlohmann::json& e = j.at("experiments").at(0);
    EXPECT_EQ(e.at("id"), "build");
    const nlohmann::json& builds = e.at("extra").at("builds");
    ASSERT_FALSE(builds.empty());
    for (const nlohmann::json& b : builds) {
        EXPECT_GT(b.at("kdtree_s").get<double>(), 0.0);
        EXPECT_GT(b.at("bvh_s").get<double>(), 0.0);
        EXPECT_GT(b.at("bvh_high_s").get<double>(), 0.0);
        if (has_tracer("embree")) {
            EXPECT_GT(b.at("embree_bvh_s").get<double>(), 0.0);
            EXPECT_GT(b.at("embree_bvh_medium_s").get<double>(), 0.0);
        }
    }
    const std::string out = read_file(dir / "out.txt");
    EXPECT_NE(out.find("kd SAH cost"), std::string::npos) << out;
    if (has_tracer("embree")) {
        EXPECT_NE(out.find("of Embree's HIGH build"), std::string::npos) << out;
        EXPECT_NE(out.find("of its MEDIUM build"), std::string::npos) << out;
    }
    std::filesystem::remove_all(dir);
}

// `rtt bench answers`: ns per answered ray for each scene and K, and the limit kernel's.
TEST(BenchCli, AnswersReportsNanosecondsPerAnsweredRay) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("rtt_bench_answers_" + std::to_string(getpid()));
    ASSERT_EQ(run_bench_cli("answers --quick --scenes room --json a.json", dir), 0)
        << read_file(dir / "err.txt");
    const nlohmann::json j = nlohmann::json::parse(read_file(dir / "a.json"));
    const nlohmann::json& e = j.at("experiments").at(0);
    EXPECT_EQ(e.at("id"), "answers");
    const nlohmann::json& cells = e.at("extra").at("answers");
    ASSERT_EQ(cells.size(), 2u);  // K = 1 and 4
    for (const nlohmann::json& c : cells) {
        EXPECT_GT(c.at("primary_answered_rays").get<uint64_t>(), 0u);
        EXPECT_GT(c.at("primary_ns_per_answered_ray").get<double>(), 0.0);
    }
    for (const char* n : {"1", "4"})
        EXPECT_GT(e.at("extra").at("limit_ns_per_ray").at(n).get<double>(), 0.0);
    std::filesystem::remove_all(dir);
}

TEST(BenchCli, RaysReportsEveryKindOnRandomAndBounceRays) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("rtt_bench_rays_" + std::to_string(getpid()));
    ASSERT_EQ(run_bench_cli("rays --quick --scenes room --json r.json", dir), 0)
        << read_file(dir / "err.txt");
    const nlohmann::json j = nlohmann::json::parse(read_file(dir / "r.json"));
    const nlohmann::json& e = j.at("experiments").at(0);
    EXPECT_EQ(e.at("id"), "rays");
    std::set<std::string> sets, kinds;
    for (const nlohmann::json& c : e.at("extra").at("rays")) {
        sets.insert(c.at("rays").get<std::string>());
        kinds.insert(c.at("kind").get<std::string>());
        EXPECT_GT(c.at("count").get<uint64_t>(), 1000u);
        EXPECT_GT(c.at("mrays_per_second").get<double>(), 0.0);
        // The run itself refuses an exact kind that differs from `ray`; Embree may tie-break.
        if (c.at("kind").get<std::string>().rfind("embree", 0) != 0) {
            EXPECT_EQ(c.at("differences_from_ray").get<uint64_t>(), 0u);
        }
    }
    EXPECT_EQ(sets, (std::set<std::string>{"random", "bounce"}));
    for (const char* k : {"ray", "packet", "rtt"}) EXPECT_TRUE(kinds.count(k)) << k;
    std::filesystem::remove_all(dir);
}

TEST(BenchCli, BadInputIsOneLineAndNonZero) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("rtt_bench_bad_" + std::to_string(getpid()));
    EXPECT_EQ(run_bench_cli("table1 --scenes no-such-scene", dir), 1);
    const std::string err = read_file(dir / "err.txt");
    EXPECT_NE(err.find("unknown scene 'no-such-scene'"), std::string::npos);
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1);
    EXPECT_EQ(run_bench_cli("table1 --quick --long", dir), 1);
    EXPECT_EQ(run_bench_cli("", dir), 2);  // a subcommand is required
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace rtt::bench
