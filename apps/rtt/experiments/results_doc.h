// The whole output of `rtt bench all`: JSON with every figure, and docs/RESULTS.md.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "experiments/experiments.h"
#include "experiments/machine_info.h"

namespace rtt::bench {

struct ResultsDocument {
    MachineInfo machine;
    std::string command;  ///< The command line that produced it.
    BenchMode mode = BenchMode::full;
    int threads = 1;
    int repetitions = 3;
    ClockKind clock = ClockKind::cpu;
    double seconds = 0;    ///< Wall time of the whole run.
    double load_end = -1;  ///< 1-minute load average at the end (machine.load_average: start).
    std::vector<ExperimentResult> experiments;
};

nlohmann::json results_json(const ResultsDocument& doc);

/// docs/RESULTS.md: machine, where we stand (every finding), then each experiment's tables and
/// plots. Paths of plots and images are written relative to `markdown_dir`.
std::string results_markdown(const ResultsDocument& doc, const std::string& markdown_dir);

}  // namespace rtt::bench
