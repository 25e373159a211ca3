#include "experiments/experiment_common.h"

#include <filesystem>

#include "rtt/error.h"

namespace rtt::bench {

const BenchScene& SceneCache::get(const std::string& name) {
    auto it = scenes_.find(name);
    if (it == scenes_.end())
        it = scenes_.emplace(name, std::make_unique<BenchScene>(load_bench_scene(name, make_tree_)))
                 .first;
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

ExperimentResult experiment_from_json(const nlohmann::json& j) {
    ExperimentResult r;
    r.id = j.at("id").get<std::string>();
    r.title = j.at("title").get<std::string>();
    for (const nlohmann::json& m : j.at("measurements"))
        r.measurements.push_back(measurement_from_json(m));
    for (const nlohmann::json& t : j.at("tables")) r.tables.push_back(table_from_json(t));
    r.files = j.at("files").get<std::vector<std::string>>();
    r.findings = j.at("findings").get<std::vector<std::string>>();
    r.extra = j.at("extra");
    return r;
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
    const Workload workload(scene, width, height, aa, MeasureOptions{}.band_samples, config.region);
    MeasureOptions options;
    options.repetitions = config.repetitions;
    options.threads = threads;
    const Measurement m = measure(workload, tracers, options);
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - config.start).count();
    std::fprintf(config.log, "  measured %s (load %.1f, %.0f s into the run)\n",
                 measurement_summary(m).c_str(), load_average(), elapsed);
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
