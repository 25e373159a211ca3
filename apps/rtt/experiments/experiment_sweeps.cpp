// Figures 7 and 8: the speed-up of rtt over the 4-wide packets (and, beside it, over the widest
// packets) as antialiasing, then resolution, grows. Both are one sweep over image
// configurations; tables and an SVG plot each.
#include "experiments/experiment_common.h"
#include "experiments/paper_data.h"
#include "experiments/plot_svg.h"

namespace rtt::bench {

using namespace detail;

namespace {

struct SweepPoint {
    int width, height, aa;
    std::string label;  ///< Column and tick label.
};

struct Sweep {
    std::string id, title, x_label, file;
    std::vector<SweepPoint> points;
    int paper_point = -1;  ///< Index of the configuration of the paper's Table 1, or -1.
};

ExperimentResult run_sweep(const BenchConfig& config, SceneCache& scenes, const Sweep& sweep) {
    const ClockKind clock = table_clock(config, config.threads);
    ExperimentResult r;
    r.id = sweep.id;
    r.title = sweep.title;
    std::fprintf(config.log, "\n== %s\n", r.title.c_str());
    const std::string wide = widest_packet();
    const std::vector<std::string> kinds = available({"packet", wide, "rtt"});
    for (const std::string& name : config.scenes) {
        const BenchScene& scene = scenes.get(name);
        const std::vector<NamedTracer> tracers = make_tracers(scene, kinds);
        for (const SweepPoint& p : sweep.points)
            r.measurements.push_back(
                run_measurement(config, scene, tracers, p.width, p.height, p.aa, config.threads));
    }
    const size_t n = sweep.points.size();
    auto at = [&](size_t scene, size_t point) -> const Measurement& {
        return r.measurements[scene * n + point];
    };

    TextTable speed, same_width, traced;
    const std::string how = std::to_string(config.threads) + " thread(s), " + clock_name(clock) +
                            " time, median of " + std::to_string(config.repetitions);
    speed.title = sweep.title + ": speed-up rtt/packet (" + how + ")";
    same_width.title = sweep.title + ": speed-up rtt/" + wide +
                       " (the widest packets, RTT's own fallback; " + how + ")";
    traced.title = sweep.title + ": rays rtt traced through the kd-tree, % of rays asked";
    speed.header = same_width.header = traced.header = {"scene, rays"};
    for (const SweepPoint& p : sweep.points) {
        speed.header.push_back(p.label);
        same_width.header.push_back(p.label);
        traced.header.push_back(p.label);
    }
    LinePlot plot;
    plot.title = sweep.title;
    plot.x_label = sweep.x_label;
    plot.y_label = "speed-up rtt / packet (" + std::string(clock_name(clock)) + " time)";
    plot.reference_y = 1.0;
    for (size_t i = 0; i < n; ++i) {
        plot.x_ticks.push_back(double(i));
        plot.x_tick_labels.push_back(sweep.points[i].label);
    }
    for (size_t s = 0; s < config.scenes.size(); ++s) {
        const std::string& name = config.scenes[s];
        for (bool shadow : {false, true}) {
            const std::string rays = shadow ? "shadow" : "primary";
            std::vector<std::string> srow{name + ", " + rays}, wrow{name + ", " + rays},
                trow{name + ", " + rays};
            PlotSeries series;
            series.label = name + " " + rays;
            series.color = scene_color(name);
            series.dashed = shadow;
            for (size_t i = 0; i < n; ++i) {
                const Measurement& m = at(s, i);
                const double v = speedup(m, "rtt", "packet", shadow, clock);
                srow.push_back(format_ratio(v));
                wrow.push_back(format_ratio(speedup(m, "rtt", wide, shadow, clock)));
                const TracerResult* q = m.find("rtt");
                const KindResult* k = q ? &(shadow ? q->shadow : q->primary) : nullptr;
                trow.push_back(
                    k && k->rays
                        ? format_fixed(100.0 * double(k->stats.traced) / double(k->rays), 1)
                        : "-");
                if (v > 0) {
                    series.x.push_back(double(i));
                    series.y.push_back(v);
                }
            }
            speed.rows.push_back(srow);
            same_width.rows.push_back(wrow);
            traced.rows.push_back(trow);
            plot.series.push_back(series);
        }
    }
    // The paper's Table 1 speed-ups as hollow markers in the scene's colour (squares: shadow).
    for (const std::string& name : config.scenes)
        for (bool shadow : {false, true}) {
            const paper::Table1Column* p = paper::table1_column(name);
            if (!p || sweep.paper_point < 0) continue;
            PlotSeries reference;
            reference.label = name + (shadow ? " shadow" : " primary") + ", paper";
            reference.color = scene_color(name);
            reference.markers_only = true;
            reference.dashed = shadow;
            reference.x = {double(sweep.paper_point)};
            reference.y = {shadow ? p->shadow_speedup() : p->primary_speedup()};
            plot.series.push_back(reference);
        }
    if (sweep.paper_point >= 0)
        speed.notes.push_back(
            "The paper's Table 1 speed-ups (640x480, 1x1): room 1.23x / 1.17x, "
            "office 1.11x / 1.24x, plants 0.95x / 1.09x (primary / shadow).");
    for (const std::string& note : agreement_notes(r.measurements)) speed.notes.push_back(note);
    print_table(config.log, speed);
    print_table(config.log, same_width);
    print_table(config.log, traced);
    r.tables = {speed, same_width, traced};
    if (!has_tracer("rtt")) {
        r.findings.push_back("no 'rtt' tracer in this build: nothing to plot");
        return r;
    }
    const std::string path = output_path(config, sweep.file);
    write_svg(path, plot);
    r.files.push_back(path);
    std::fprintf(config.log, "  wrote %s\n", path.c_str());
    for (size_t s = 0; s < config.scenes.size(); ++s) {
        const Measurement& first = at(s, 0);
        const Measurement& last = at(s, n - 1);
        r.findings.push_back(config.scenes[s] + ": primary " +
                             format_ratio(speedup(first, "rtt", "packet", false, clock)) + " at " +
                             sweep.points.front().label + " -> " +
                             format_ratio(speedup(last, "rtt", "packet", false, clock)) + " at " +
                             sweep.points.back().label + "; shadow " +
                             format_ratio(speedup(first, "rtt", "packet", true, clock)) + " -> " +
                             format_ratio(speedup(last, "rtt", "packet", true, clock)) + "; rtt/" +
                             wide + " primary " +
                             format_ratio(speedup(first, "rtt", wide, false, clock)) + " -> " +
                             format_ratio(speedup(last, "rtt", wide, false, clock)) + ", shadow " +
                             format_ratio(speedup(first, "rtt", wide, true, clock)) + " -> " +
                             format_ratio(speedup(last, "rtt", wide, true, clock)));
    }
    return r;
}

}  // namespace

ExperimentResult run_fig7(const BenchConfig& config, SceneCache& scenes) {
    // The paper's 640x480 costs 91 frames of Table 1 per scene; the full mode halves each side.
    const int w = config.by_mode(64, 320, 640), h = config.by_mode(48, 240, 480);
    Sweep sweep;
    sweep.id = "fig7";
    sweep.title = "Figure 7: speed-up against antialiasing, " + size_label(w, h);
    sweep.x_label = "antialiasing (samples per pixel)";
    sweep.file = "fig7_antialiasing.svg";
    for (int k = 1; k <= 6; ++k)
        sweep.points.push_back({w, h, k, std::to_string(k) + "x" + std::to_string(k)});
    if (!config.quick()) sweep.paper_point = 0;
    return run_sweep(config, scenes, sweep);
}

ExperimentResult run_fig8(const BenchConfig& config, SceneCache& scenes) {
    Sweep sweep;
    sweep.id = "fig8";
    sweep.title = "Figure 8: speed-up against resolution, 1x1";
    sweep.x_label = "image resolution";
    sweep.file = "fig8_resolution.svg";
    const int full[5][2] = {{320, 240}, {640, 480}, {1024, 768}, {1600, 1200}, {2048, 1536}};
    const int quick[5][2] = {{32, 24}, {64, 48}, {96, 72}, {128, 96}, {160, 120}};
    for (const auto& s : config.quick() ? quick : full)
        sweep.points.push_back({s[0], s[1], 1, size_label(s[0], s[1])});
    if (!config.quick()) sweep.paper_point = 1;
    return run_sweep(config, scenes, sweep);
}

}  // namespace rtt::bench
