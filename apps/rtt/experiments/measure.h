// The timing harness: every tracer of a set answers the same Workload, band by band; answers are
// checked against a baseline tracer before anything is timed, and the timed repetitions
// interleave the tracers so that drift of a shared, noisy machine hits them all alike.
//
// Per band:
//  1. Checking pass (also the warm-up): each tracer traces the band's primary tiles with
//     statistics; the baseline's hits define the band's shadow segments (Workload::add_shadows);
//     each tracer answers them. Answers are compared with the baseline's: closest hits (t and
//     triangle) for primary rays, visibility for active segments.
//  2. R timed repetitions. Repetition r runs the primary tiles with every tracer, starting with
//     tracer r mod T (so no tracer always runs first), then the shadow tiles likewise. Only the
//     tracer calls are timed, without statistics.
// A tracer's time for the frame is the sum over bands of the median over repetitions (robust to
// a preemption hitting one band of one repetition); per-repetition frame totals are kept too.
//
// Threads: with 1 thread every timed call runs on the calling thread; with N > 1 the band's
// tiles are spread over a oneTBB arena of N threads. The checking pass, untimed, uses every core.
// No CPU affinity is set. Two clocks are read around every timed stretch: wall (steady clock) and
// CPU time (the calling thread's with 1 thread, the process's with N), because on a shared machine
// CPU time of one thread is the steadier estimate of what an idle machine would show.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "experiments/workload.h"
#include "rtt/rtt_options.h"
#include "rtt/tracer.h"

namespace rtt::bench {

/// Wall and CPU seconds of one timed stretch (or a sum of them).
struct Clocks {
    double wall = 0;
    double cpu = 0;
    Clocks& operator+=(const Clocks& o) {
        wall += o.wall;
        cpu += o.cpu;
        return *this;
    }
};

/// Which clock tables and speed-ups use.
enum class ClockKind { cpu, wall };

/// One tracer on one kind of rays (primary or shadow) over a whole frame.
struct KindResult {
    TraceStats stats;          ///< From the checking pass (rays, traced).
    RttStats rtt;              ///< From the checking pass (answered, lists; RTT tracers).
    uint64_t rays = 0;         ///< Rays (active segments) asked for: the Mrays/s numerator.
    Clocks time;               ///< Sum over bands of the median over repetitions.
    std::vector<Clocks> reps;  ///< Frame totals per repetition (sum over bands).
    uint64_t differences = 0;  ///< Answers different from the baseline's.

    double seconds(ClockKind clock) const { return clock == ClockKind::cpu ? time.cpu : time.wall; }
    /// Million rays per second on `clock`; 0 when nothing was timed.
    double mrays_per_second(ClockKind clock) const;
};

/// A tracer built over one scene, with what it cost to build.
struct NamedTracer {
    std::string kind;
    std::unique_ptr<Tracer> tracer;
    /// False for tracers with their own arithmetic (Embree): a different answer from the
    /// baseline is then an exact tie broken differently, reported but not an error.
    bool exact = true;
    double own_build_seconds = -1;  ///< Embree's BVH build; -1 for kd-tree tracers.
};

/// make_tracer(kind, ...) as the benchmarks use it: `rtt` with its BVH built at setup
/// (RttOptions::bvh_at_setup), the state a long render reaches, so frames are timed apart
/// from builds as for every other tracer; its build is in rtt's setup time.
std::unique_ptr<Tracer> make_bench_tracer(const std::string& kind, const Scene& scene,
                                          const KdTree& tree);

/// Builds the tracers of `kinds` over `scene` (kinds this build lacks are skipped), on the
/// calling thread's oneTBB arena. Throws rtt::Error if `kinds` names an unknown tracer.
std::vector<NamedTracer> make_tracers(const BenchScene& scene,
                                      const std::vector<std::string>& kinds);

/// True when this build has tracer `kind`.
bool has_tracer(const std::string& kind);

struct TracerResult {
    std::string kind;
    bool exact = true;
    KindResult primary;
    KindResult shadow;
};

struct MeasureOptions {
    std::string baseline =
        "packet";         ///< Its hits define the shadow segments; answers compared to it.
    int repetitions = 3;  ///< Timed repetitions after the checking pass (>= 1).
    int threads = 1;      ///< Tracing threads of the timed repetitions (>= 1).
    /// Threads of the untimed checking pass; 0 = all cores (it only has to be correct).
    int check_threads = 0;
    bool shadows = true;                    ///< Also measure shadow rays.
    size_t band_samples = size_t(1) << 16;  ///< Samples per band (see Workload).
};

/// Everything measured on one workload.
struct Measurement {
    std::string scene;
    int width = 0, height = 0, aa = 1;
    int threads = 1;
    int repetitions = 0;
    std::string baseline;
    uint64_t primary_rays = 0;  ///< Per tracer and frame.
    uint64_t shadow_rays = 0;   ///< Active segments per tracer and frame.
    size_t shadow_tiles = 0;    ///< (tile, light) pairs traced.
    double seconds = 0;         ///< Wall time of the whole measurement, checking included.
    std::vector<TracerResult> tracers;

    /// The result of `kind`, or nullptr when it was not measured.
    const TracerResult* find(const std::string& kind) const;
    /// Differences from the baseline summed over the exact tracers (must be 0).
    uint64_t mismatches() const;
};

/// Measures every tracer of `tracers` (which must include options.baseline) on `workload`.
/// Throws rtt::Error when the baseline is missing or an option is out of range.
Measurement measure(const Workload& workload, const std::vector<NamedTracer>& tracers,
                    const MeasureOptions& options);

/// t_baseline / t_kind on `clock` (> 1: `kind` is faster); 0 when either is missing.
double speedup(const Measurement& m, const std::string& kind, const std::string& baseline,
               bool shadow, ClockKind clock);

}  // namespace rtt::bench
