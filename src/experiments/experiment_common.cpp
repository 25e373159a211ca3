#include "experiments/experiment_common.h"

#include <filesystem>

#include "rtt/error.h"

namespace rtt::bench {

const BenchScene& SceneCache::get(const std::string& name) {
    auto it = scenes_.find(name);
    if (it == scenes_.end())
        it = scenes_.emplace(name, std::make_unique<BenchScene>(load_bench_scene(name))).first;
    return *it->second;
}

nlohmann::json experiment_json(const ExperimentResult& result) {
    nlohmann::json measurements = nlohmann::json::array(), tables = nlohmann::json::array();
    for (const Measurement& m : result.measurements) measurements.push_back(measurement_json(m));
    for (const TextTable& t : result.tables) tables.push_back(table_json(t));
    return {{"id", result.id},       {"title", result.title},
            {"tables", tables},      {"measurements", measurements},
            {"files", result.files}, {"findings", result.findings},
            {"extra", result.extra}};
}

const char* mode_name(BenchMode mode) {
    return mode == BenchMode::quick ? "quick" : mode == BenchMode::full ? "full" : "long";
}

namespace detail {

ClockKind table_clock(const BenchConfig& config, int threads) {
    return threads > 1 ? ClockKind::wall : config.clock;
}

const char* clock_name(ClockKind clock) {
    return clock == ClockKind::cpu ? "CPU" : "wall";
}

std::vector<std::string> available(const std::vector<std::string>& wanted) {
    std::vector<std::string> out;
    for (const std::string& k : wanted)
        if (has_tracer(k)) out.push_back(k);
    return out;
}

std::string widest_packet() {
    for (const char* k : {"packet16", "packet8"})
        if (has_tracer(k)) return k;
    return "packet";
}

std::string against_widest(const Measurement& m, ClockKind clock) {
    const std::string wide = widest_packet();
    return "rtt/" + wide + " " + format_ratio(speedup(m, "rtt", wide, false, clock)) + " / " +
           format_ratio(speedup(m, "rtt", wide, true, clock));
}

Measurement run_measurement(const BenchConfig& config, const BenchScene& scene,
                            const std::vector<NamedTracer>& tracers, int width, int height, int aa,
                            int threads) {
    const Workload workload(scene, width, height, aa, MeasureOptions{}.band_samples,
                            config.region);
    MeasureOptions options;
    options.repetitions = config.repetitions;
    options.threads = threads;
    const Measurement m = measure(workload, tracers, options);
    std::fprintf(config.log, "  measured %s (load %.1f)\n", measurement_summary(m).c_str(),
                 load_average());
    std::fflush(config.log);
    return m;
}

std::string size_label(int width, int height) {
    return std::to_string(width) + "x" + std::to_string(height);
}

std::string output_path(const BenchConfig& config, const std::string& file) {
    std::error_code ec;
    std::filesystem::create_directories(config.out_dir, ec);
    if (ec) throw Error(config.out_dir, 0, "cannot create the output folder: " + ec.message());
    return (std::filesystem::path(config.out_dir) / file).string();
}

std::string verdict(double value, double target) {
    if (value <= 0) return "not measured";
    return value >= target ? "met" : "missed";
}

std::string scene_color(const std::string& scene) {
    if (scene == "room") return "#1f77b4";
    if (scene == "office") return "#d62728";
    if (scene == "plants") return "#2ca02c";
    static const char* others[] = {"#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22"};
    return others[std::hash<std::string>{}(scene) % 5];
}

}  // namespace detail
}  // namespace rtt::bench
