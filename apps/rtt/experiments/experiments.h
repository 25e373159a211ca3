// The paper's experiments (section 4) and the Embree comparison, each as one function that
// measures, prints its tables as it goes and returns everything for JSON and Markdown.
//
//   table1  Table 1: room, office, plants at 640x480, K = 1: packet vs rtt, primary and shadow.
//   fig7    Figure 7: speed-up rtt/packet against antialiasing 1x1 .. 6x6 at 640x480.
//   fig8    Figure 8: speed-up against resolution 320x240 .. 2048x1536, K = 1.
//   hq      Section 4's "2.43 times" point: room at 2048x1536 (the paper: 2048x1560), 6x6.
//   fig5    Figure 5: office rendered, and its RTT maps for primary and shadow rays.
//   embree  packet, packet16, frustum, rtt and Embree at 1024x768, K = 1 and 4, 1 thread and
//           all cores; kd-tree and BVH build times.
//   build   the kd-tree and BVH build times alone (not part of `all`: `embree` has them).
//   answers ns per ray rtt answers from a list, primary and shadow, K = 1 and 4, beside the
//           limit of an answer (not part of `all`).
//   rays    random and bounce rays, closest hit and visibility, every exact kind beside Embree's
//           single rays, stream and packets, 1 thread and all cores (not part of `all`).
// Sizes by mode: --quick keeps every experiment's shape with tiny images and one repetition
// (a smoke test); the default full mode runs the paper's sizes except where a configuration
// would not fit in 10-15 minutes on a 2-core machine (Figure 7 at 320x240, Embree's K = 4
// at 512x384), which --long runs too (about half an hour).
#pragma once

#include <chrono>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "experiments/measure.h"
#include "experiments/report.h"
#include "experiments/workload.h"

namespace rtt::bench {

enum class BenchMode { quick, full, long_run };

struct BenchConfig {
    std::vector<std::string> scenes{"room", "office", "plants"};
    int threads = 1;  ///< Tracing threads (the embree experiment adds all cores).
    BenchMode mode = BenchMode::full;
    int repetitions = 3;  ///< Timed repetitions per measurement.
    int region = 0;       ///< RenderOptions::region of the workloads (0 = default per K).
    ClockKind clock = ClockKind::cpu;
    std::string out_dir = "bench-results";  ///< Plots and images.
    std::FILE* log = stdout;                ///< Tables and progress.
    /// When the run started: progress lines show the time elapsed since.
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();

    bool quick() const { return mode == BenchMode::quick; }
    /// The value for this config's mode.
    template <typename T>
    T by_mode(T quick_value, T full_value, T long_value) const {
        return mode == BenchMode::quick  ? quick_value
               : mode == BenchMode::full ? full_value
                                         : long_value;
    }
};

/// "quick", "full" or "long".
const char* mode_name(BenchMode mode);

/// Scenes loaded on first use and kept for the following experiments.
class SceneCache {
public:
    /// `make_tree`: as load_bench_scene's.
    explicit SceneCache(std::function<KdTree(const std::string& name, const Scene&)> make_tree = {})
        : make_tree_(std::move(make_tree)) {}

    /// Throws rtt::Error for an unknown scene or a bad file.
    const BenchScene& get(const std::string& name);

private:
    std::function<KdTree(const std::string& name, const Scene&)> make_tree_;
    std::map<std::string, std::unique_ptr<BenchScene>> scenes_;
};

struct ExperimentResult {
    std::string id;
    std::string title;
    std::vector<Measurement> measurements;
    std::vector<TextTable> tables;
    std::vector<std::string> files;     ///< Plots and images written (paths).
    std::vector<std::string> findings;  ///< One-line readings (speed-ups against targets).
    nlohmann::json extra = nlohmann::json::object();  ///< Build times and other figures.
};

ExperimentResult run_table1(const BenchConfig& config, SceneCache& scenes);
ExperimentResult run_fig7(const BenchConfig& config, SceneCache& scenes);
ExperimentResult run_fig8(const BenchConfig& config, SceneCache& scenes);
ExperimentResult run_hq(const BenchConfig& config, SceneCache& scenes);
ExperimentResult run_fig5(const BenchConfig& config, SceneCache& scenes);
ExperimentResult run_embree(const BenchConfig& config, SceneCache& scenes);
ExperimentResult run_build(const BenchConfig& config, SceneCache& scenes);
ExperimentResult run_answers(const BenchConfig& config, SceneCache& scenes);
ExperimentResult run_rays(const BenchConfig& config, SceneCache& scenes);

/// Appends the kd-tree and Embree build table (run_build's) to `r`.
void add_build_table(const BenchConfig& config, SceneCache& scenes, ExperimentResult& r);

/// Every figure of a result (tables, measurements, files, findings, extra).
nlohmann::json experiment_json(const ExperimentResult& result);
/// The inverse of experiment_json.
ExperimentResult experiment_from_json(const nlohmann::json& j);

/// `rtt` without arguments: RTT against the 4-wide packets on `scene` at 640x480, K = 1 (the
/// paper's Table 1), and at 320x240 with K = 4, one thread, 3 repetitions; prints times, rays
/// traced, speed-ups and agreement.
/// Does nothing but say so when this build has no "rtt" tracer.
void print_rtt_vs_packet(std::FILE* out, const std::string& scene);

}  // namespace rtt::bench
