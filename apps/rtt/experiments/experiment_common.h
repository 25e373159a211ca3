// Pieces shared by the experiment files (not used outside apps/rtt/experiments).
#pragma once

#include <string>
#include <vector>

#include "experiments/experiments.h"

namespace rtt::bench::detail {

/// The clock a table uses: the configured one with 1 thread; wall time with several (CPU time
/// summed over threads is not what a user waits for).
ClockKind table_clock(const BenchConfig& config, int threads);
/// "CPU" or "wall".
const char* clock_name(ClockKind clock);

/// The kinds of `wanted` this build has, in order.
std::vector<std::string> available(const std::vector<std::string>& wanted);

/// The widest packet tracer of this build ("packet16", else "packet8", else "packet"): the
/// width of RTT's own fallback, so rtt against it is the same-width comparison.
std::string widest_packet();

/// "rtt/packet16 0.73x / 0.74x": rtt against the widest packets, primary / shadow.
std::string against_widest(const Measurement& m, ClockKind clock);

/// Measures `tracers` on scene x (w, h, K) with the config's repetitions, logging one line.
Measurement run_measurement(const BenchConfig& config, const BenchScene& scene,
                            const std::vector<NamedTracer>& tracers, int width, int height, int aa,
                            int threads);

/// "640x480".
std::string size_label(int width, int height);

/// Path of `file` inside the config's output folder (created on demand).
std::string output_path(const BenchConfig& config, const std::string& file);

/// The speed-up finding of one scene against a target: "met" / "missed".
std::string verdict(double value, double target);

/// Line colour of a scene in plots (stable per built-in scene).
std::string scene_color(const std::string& scene);

}  // namespace rtt::bench::detail
