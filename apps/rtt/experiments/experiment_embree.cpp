// Embree beside our tracers on the very same tiles: primary and shadow throughput of packet,
// packet16, frustum, rtt and every Embree mode (16-wide packets, stream, single rays; HIGH and
// MEDIUM builds) in one run, three scenes at 1024x768 with K = 1 and 4, on one thread and on all
// cores, and rtt's ratio to the fastest Embree mode of each cell; then kd-tree and BVH build
// times side by side.
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>

#include "experiments/experiment_common.h"
#include "trace/trace_embree.h"

namespace rtt::bench {

using namespace detail;

namespace {

/// Every Embree mode, HIGH and MEDIUM builds (src/trace/factories.h, EmbreeMode).
const std::vector<std::string> embree_modes = {
    "embree",        "embree-stream",        "embree1",
    "embree-medium", "embree-stream-medium", "embree1-medium"};

/// The fastest Embree mode measured in `m` (primary or shadow rays), or "" when none was.
std::string fastest_embree(const Measurement& m, bool shadow, ClockKind clock) {
    std::string best;
    double best_rate = 0.0;
    for (const std::string& k : embree_modes)
        if (const TracerResult* r = m.find(k)) {
            const double rate = (shadow ? r->shadow : r->primary).mrays_per_second(clock);
            if (rate > best_rate) {
                best_rate = rate;
                best = k;
            }
        }
    return best;
}

TextTable throughput_table(const std::vector<Measurement>& ms,
                           const std::vector<std::string>& kinds, int threads, bool shadow,
                           ClockKind clock, int repetitions) {
    TextTable t;
    t.title = std::string(shadow ? "Shadow" : "Primary") + " Mrays/s, " + std::to_string(threads) +
              " thread(s) (" + clock_name(clock) + " time, median of " +
              std::to_string(repetitions) + ")";
    t.header = {"scene", "size", "K"};
    for (const std::string& k : kinds) t.header.push_back(k);
    const bool both = std::count(kinds.begin(), kinds.end(), "rtt") &&
                      std::count(kinds.begin(), kinds.end(), "embree");
    if (both) {
        t.header.push_back("fastest Embree");
        t.header.push_back("rtt/fastest");
    }
    for (const Measurement& m : ms) {
        if (m.threads != threads) continue;
        std::vector<std::string> row{m.scene, size_label(m.width, m.height), std::to_string(m.aa)};
        for (const std::string& k : kinds) {
            const TracerResult* r = m.find(k);
            row.push_back(
                r ? format_fixed((shadow ? r->shadow : r->primary).mrays_per_second(clock), 1)
                  : "-");
        }
        if (both) {
            const std::string best = fastest_embree(m, shadow, clock);
            row.push_back(best.empty() ? "-" : best);
            row.push_back(best.empty() ? "-"
                                       : format_ratio(speedup(m, "rtt", best, shadow, clock)));
        }
        t.rows.push_back(row);
    }
    return t;
}

/// Seconds of one frame's primary and shadow rays by the fastest of `modes` measured in `m`
/// (-1 when none was).
double fastest_frame(const Measurement& m, const std::vector<std::string>& modes, ClockKind clock) {
    double best = -1.0;
    for (const std::string& k : modes)
        if (const TracerResult* t = m.find(k)) {
            const double s = t->primary.seconds(clock) + t->shadow.seconds(clock);
            if (best < 0.0 || s < best) best = s;
        }
    return best;
}

/// The first image: the acceleration structure's build (add_build_table) plus one K = 1 frame of
/// primary and shadow rays: rtt (kd-tree, its tracer's setup, its frame), bvh (its BVH, its
/// frame) and Embree with its HIGH and its MEDIUM build (each with the fastest of its modes),
/// per scene and thread count.
void add_first_image_table(const BenchConfig& config, ExperimentResult& r) {
    if (!r.extra.contains("builds") || !has_tracer("embree")) return;
    TextTable t;
    t.title =
        "First image (seconds): build (wall) + one K=1 frame of primary and shadow rays "
        "(the tables' clock), rtt and bvh beside Embree's fastest mode with each build";
    t.header = {"scene",
                "threads",
                "rtt: kd-tree + setup + frame",
                "bvh: BVH + frame",
                "Embree HIGH",
                "Embree MEDIUM",
                "MEDIUM / rtt",
                "MEDIUM / bvh"};
    nlohmann::json json = nlohmann::json::array();
    for (const auto& b : r.extra["builds"]) {
        const std::string scene = b["scene"];
        const int threads = b["threads"];
        const auto m = std::find_if(r.measurements.begin(), r.measurements.end(), [&](auto& x) {
            return x.scene == scene && x.threads == threads && x.aa == 1;
        });
        if (m == r.measurements.end() || !m->find("rtt")) continue;
        const ClockKind clock = table_clock(config, threads);
        const double rtt =
            double(b["kdtree_s"]) + double(b["rtt_setup_s"]) + fastest_frame(*m, {"rtt"}, clock);
        const double bvh_frame = fastest_frame(*m, {"bvh"}, clock);
        const double bvh = bvh_frame < 0.0 ? -1.0 : double(b["bvh_s"]) + bvh_frame;
        const double high = double(b["embree_bvh_s"]) +
                            fastest_frame(*m, {"embree", "embree-stream", "embree1"}, clock);
        const double medium =
            double(b["embree_bvh_medium_s"]) +
            fastest_frame(*m, {"embree-medium", "embree-stream-medium", "embree1-medium"}, clock);
        t.rows.push_back({scene, std::to_string(threads), format_fixed(rtt, 3),
                          bvh < 0.0 ? "-" : format_fixed(bvh, 3), format_fixed(high, 3),
                          format_fixed(medium, 3), format_ratio(medium / rtt),
                          bvh < 0.0 ? "-" : format_ratio(medium / bvh)});
        r.findings.push_back(scene + ", " + std::to_string(threads) +
                             " thread(s): first image (build + K=1 frame) rtt " +
                             format_fixed(rtt, 3) + " s, Embree MEDIUM " + format_fixed(medium, 3) +
                             " s: rtt at " + format_ratio(medium / rtt) + " of its speed");
        json.push_back({{"scene", scene},
                        {"threads", threads},
                        {"rtt_s", rtt},
                        {"bvh_s", bvh},
                        {"embree_high_s", high},
                        {"embree_medium_s", medium}});
    }
    print_table(config.log, t);
    r.tables.push_back(t);
    r.extra["first_image"] = json;
}

}  // namespace

ExperimentResult run_embree(const BenchConfig& config, SceneCache& scenes) {
    // (K, width, height): K = 4 at 1024x768 is 12.6 M samples per tracer and repetition, so
    // the default full mode runs it at 512x384 and only --long at the size.
    const int w1 = config.quick() ? 128 : 1024, h1 = config.quick() ? 96 : 768;
    const int w4 = config.by_mode(64, 512, 1024), h4 = config.by_mode(48, 384, 768);
    const int all = std::max(1, tbb::info::default_concurrency());
    std::vector<int> thread_counts{1};
    if (all > 1) thread_counts.push_back(all);
    ExperimentResult r;
    r.id = "embree";
    r.title = "Embree 3 beside packet, packet16, frustum, rtt and bvh at " + size_label(w1, h1) +
              " (K=1) and " + size_label(w4, h4) + " (K=4)";
    std::fprintf(config.log, "\n== %s\n", r.title.c_str());
    std::vector<std::string> wanted{"packet", "packet16", "frustum", "rtt", "bvh"};
    wanted.insert(wanted.end(), embree_modes.begin(), embree_modes.end());
    const std::vector<std::string> kinds = available(wanted);
    for (const std::string& name : config.scenes) {
        const BenchScene& scene = scenes.get(name);
        const std::vector<NamedTracer> tracers = make_tracers(scene, kinds);
        for (int threads : thread_counts)
            for (int k : {1, 4})
                r.measurements.push_back(run_measurement(config, scene, tracers, k == 1 ? w1 : w4,
                                                         k == 1 ? h1 : h4, k, threads));
    }
    for (int threads : thread_counts)
        for (bool shadow : {false, true}) {
            TextTable t = throughput_table(r.measurements, kinds, threads, shadow,
                                           table_clock(config, threads), config.repetitions);
            if (!has_tracer("embree"))
                t.notes.push_back("This build has no Embree: the embree column is missing.");
            if (threads == thread_counts.back() && shadow)
                for (const std::string& n : agreement_notes(r.measurements)) t.notes.push_back(n);
            print_table(config.log, t);
            r.tables.push_back(t);
        }

    add_build_table(config, scenes, r);
    add_first_image_table(config, r);

    // Where rtt stands against Embree at its best, the fastest mode of each cell (the project's
    // ambition: faster on primary and shadow rays of room and office).
    int ambition_met = 0, ambition_total = 0;
    for (const Measurement& m : r.measurements) {
        const ClockKind clock = table_clock(config, m.threads);
        const std::string best_p = fastest_embree(m, false, clock);
        const std::string best_s = fastest_embree(m, true, clock);
        if (!m.find("rtt") || best_p.empty() || best_s.empty()) continue;
        const double p = speedup(m, "rtt", best_p, false, clock);
        const double s = speedup(m, "rtt", best_s, true, clock);
        if (m.scene == "room" || m.scene == "office") {
            ambition_total += 2;
            ambition_met += (p >= 1.0) + (s >= 1.0);
        }
        auto word = [](double v) { return v >= 1.0 ? "ahead" : "behind"; };
        r.findings.push_back(m.scene + " K=" + std::to_string(m.aa) + ", " +
                             std::to_string(m.threads) + " thread(s): rtt/fastest Embree " +
                             format_ratio(p) + " primary (" + word(p) + ", " + best_p + "), " +
                             format_ratio(s) + " shadow (" + word(s) + ", " + best_s + ")");
    }
    if (ambition_total > 0)
        r.findings.insert(r.findings.begin(),
                          "ambition (rtt faster than Embree's fastest mode on room and office, "
                          "primary and shadow): met in " +
                              std::to_string(ambition_met) + " of " +
                              std::to_string(ambition_total) + " measurements");
    return r;
}

}  // namespace rtt::bench
