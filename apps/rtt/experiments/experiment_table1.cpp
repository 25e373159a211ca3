// Table 1 of the paper, and section 4's high-resolution point (room, 2048x1536, 6x6).
#include <algorithm>
#include <functional>

#include "experiments/experiment_common.h"
#include "experiments/paper_data.h"

namespace rtt::bench {

using namespace detail;

namespace {

/// One row of Table 1: our cell from a measurement, the paper's from its column.
struct Table1Row {
    std::string label;
    std::function<std::string(const Measurement&, ClockKind)> ours;
    std::function<std::string(const paper::Table1Column&)> paper;
};

std::string ms_of(const Measurement& m, const std::string& kind, bool shadow, ClockKind clock) {
    const TracerResult* t = m.find(kind);
    return t ? format_ms((shadow ? t->shadow : t->primary).seconds(clock)) : "-";
}

std::string stat_of(const Measurement& m, const std::string& kind, bool shadow,
                    const std::function<std::string(const KindResult&)>& f) {
    const TracerResult* t = m.find(kind);
    return t ? f(shadow ? t->shadow : t->primary) : "-";
}

std::vector<Table1Row> table1_rows() {
    std::vector<Table1Row> rows;
    for (bool shadow : {false, true}) {
        const std::string kind = shadow ? "shadow" : "primary";
        auto pick = [shadow](double a, double b) { return shadow ? b : a; };
        rows.push_back(
            {"packet " + kind + " time, ms",
             [=](const Measurement& m, ClockKind c) { return ms_of(m, "packet", shadow, c); },
             [=](const paper::Table1Column& p) {
                 return format_fixed(pick(p.simd_primary_ms, p.simd_shadow_ms), 1);
             }});
        rows.push_back(
            {"  #" + kind + " rays",
             [=](const Measurement& m, ClockKind) {
                 return stat_of(m, "packet", shadow,
                                [](const KindResult& k) { return format_count(k.rays); });
             },
             [=](const paper::Table1Column& p) {
                 return format_count(uint64_t(pick(p.simd_primary_rays, p.simd_shadow_rays)));
             }});
        rows.push_back(
            {"rtt " + kind + " time, ms",
             [=](const Measurement& m, ClockKind c) { return ms_of(m, "rtt", shadow, c); },
             [=](const paper::Table1Column& p) {
                 return format_fixed(pick(p.rtt_primary_ms, p.rtt_shadow_ms), 1);
             }});
        rows.push_back(
            {"  #" + kind + " rays traced",
             [=](const Measurement& m, ClockKind) {
                 return stat_of(m, "rtt", shadow,
                                [](const KindResult& k) { return format_count(k.stats.traced); });
             },
             [=](const paper::Table1Column& p) {
                 return format_count(uint64_t(pick(p.rtt_primary_rays, p.rtt_shadow_rays)));
             }});
        rows.push_back({"  avg relevant triangles",
                        [=](const Measurement& m, ClockKind) {
                            return stat_of(m, "rtt", shadow, [](const KindResult& k) {
                                return format_fixed(k.rtt.avg_relevant(), 3);
                            });
                        },
                        [=](const paper::Table1Column& p) {
                            return format_fixed(
                                pick(p.rtt_primary_avg_relevant, p.rtt_shadow_avg_relevant), 3);
                        }});
        rows.push_back({"speed-up rtt/packet " + kind,
                        [=](const Measurement& m, ClockKind c) {
                            return format_ratio(speedup(m, "rtt", "packet", shadow, c));
                        },
                        [=](const paper::Table1Column& p) {
                            return format_ratio(shadow ? p.shadow_speedup() : p.primary_speedup());
                        }});
        const std::string wide = widest_packet();
        rows.push_back({"speed-up rtt/" + wide + " " + kind,
                        [=](const Measurement& m, ClockKind c) {
                            return format_ratio(speedup(m, "rtt", wide, shadow, c));
                        },
                        [](const paper::Table1Column&) { return std::string("-"); }});
        // The large-packet tracer RTT falls back to, alone (shadows: the widest packets).
        rows.push_back(
            {"frustum " + kind + " time, ms",
             [=](const Measurement& m, ClockKind c) { return ms_of(m, "frustum", shadow, c); },
             [](const paper::Table1Column&) { return std::string("-"); }});
        rows.push_back({"Mrays/s " + kind + " packet / rtt",
                        [=](const Measurement& m, ClockKind c) {
                            std::string s = stat_of(m, "packet", shadow, [c](const KindResult& k) {
                                return format_fixed(k.mrays_per_second(c), 1);
                            });
                            return s + " / " + stat_of(m, "rtt", shadow, [c](const KindResult& k) {
                                       return format_fixed(k.mrays_per_second(c), 1);
                                   });
                        },
                        [](const paper::Table1Column&) { return std::string("-"); }});
    }
    return rows;
}

}  // namespace

ExperimentResult run_table1(const BenchConfig& config, SceneCache& scenes) {
    const int w = config.quick() ? 160 : 640, h = config.quick() ? 120 : 480;
    const ClockKind clock = table_clock(config, config.threads);
    ExperimentResult r;
    r.id = "table1";
    r.title = "Table 1: packet (4-wide SSE), frustum and rtt at " + size_label(w, h) +
              ", no antialiasing";
    std::fprintf(config.log, "\n== %s\n", r.title.c_str());
    const std::vector<std::string> kinds = available({"packet", widest_packet(), "frustum", "rtt"});
    for (const std::string& name : config.scenes) {
        const BenchScene& scene = scenes.get(name);
        r.measurements.push_back(
            run_measurement(config, scene, make_tracers(scene, kinds), w, h, 1, config.threads));
    }

    TextTable t;
    t.title = "Table 1 (" + size_label(w, h) + ", 1x1, " + std::to_string(config.threads) +
              " thread(s), " + clock_name(clock) + " time, median of " +
              std::to_string(config.repetitions) + "): ours | the paper's (2004 hardware)";
    t.header.push_back("");
    for (const Measurement& m : r.measurements) {
        t.header.push_back(m.scene);
        t.header.push_back(paper::table1_column(m.scene) ? "paper" : "");
    }
    for (const Table1Row& row : table1_rows()) {
        std::vector<std::string> cells{row.label};
        for (const Measurement& m : r.measurements) {
            cells.push_back(row.ours(m, clock));
            const paper::Table1Column* p = paper::table1_column(m.scene);
            cells.push_back(p ? row.paper(*p) : "");
        }
        t.rows.push_back(cells);
    }
    t.notes.push_back(
        "The paper: 3DS MAX plug-in on a 2.385 GHz CPU of 2004; its times compare with "
        "ours only as ratios.");
    if (!has_tracer("rtt")) t.notes.push_back("This build has no 'rtt' tracer: its rows read '-'.");
    for (const std::string& n : agreement_notes(r.measurements)) t.notes.push_back(n);
    print_table(config.log, t);
    r.tables.push_back(t);

    for (const Measurement& m : r.measurements) {
        const double sp = speedup(m, "rtt", "packet", false, clock);
        const double ss = speedup(m, "rtt", "packet", true, clock);
        std::string line = m.scene + " " + size_label(w, h) + ": rtt/packet " + format_ratio(sp) +
                           " primary, " + format_ratio(ss) + " shadow";
        if (const paper::Table1Column* p = paper::table1_column(m.scene))
            line += " (paper " + format_ratio(p->primary_speedup()) + ", " +
                    format_ratio(p->shadow_speedup()) + ")";
        line += "; " + against_widest(m, clock);
        if (!config.quick() && (m.scene == "room" || m.scene == "office"))
            line += "; issue-5 target >= " + format_ratio(paper::target_speedup_640) +
                    ": primary " + verdict(sp, paper::target_speedup_640) + ", shadow " +
                    verdict(ss, paper::target_speedup_640);
        if (!config.quick() && m.scene == "plants")
            line += "; issue-5 target never slower than packet: primary " + verdict(sp, 1.0) +
                    ", shadow " + verdict(ss, 1.0);
        r.findings.push_back(line);
    }
    return r;
}

ExperimentResult run_hq(const BenchConfig& config, SceneCache& scenes) {
    const int w = config.quick() ? 128 : 2048, h = config.quick() ? 96 : 1536, k = 6;
    const ClockKind clock = table_clock(config, config.threads);
    // The paper's point is room; with --scenes not naming it, the first scene given.
    const bool has_room =
        std::find(config.scenes.begin(), config.scenes.end(), "room") != config.scenes.end();
    const std::string name = has_room || config.scenes.empty() ? "room" : config.scenes.front();
    ExperimentResult r;
    r.id = "hq";
    r.title = "High quality: " + name + " at " + size_label(w, h) + " with 6x6 antialiasing";
    std::fprintf(config.log, "\n== %s\n", r.title.c_str());
    const BenchScene& scene = scenes.get(name);
    const std::string wide = widest_packet();
    r.measurements.push_back(
        run_measurement(config, scene, make_tracers(scene, available({"packet", wide, "rtt"})), w,
                        h, k, config.threads));
    const Measurement& m = r.measurements.back();

    TextTable t;
    t.title = r.title + " (" + std::to_string(config.threads) + " thread(s), " + clock_name(clock) +
              " time, median of " + std::to_string(config.repetitions) + ")";
    t.header = {"rays",   "count",      "packet ms", wide + " ms",
                "rtt ms", "rtt traced", "speed-up",  "rtt/" + wide};
    // Seconds of one tracer for one kind of ray (-1: not in this build).
    const auto seconds = [&](const std::string& kind, bool shadow) {
        const TracerResult* q = m.find(kind);
        return q ? (shadow ? q->shadow : q->primary).seconds(clock) : -1.0;
    };
    const auto ms = [](double s) { return s >= 0 ? format_ms(s) : std::string("-"); };
    double packet_total = 0, wide_total = 0, rtt_total = 0;
    for (bool shadow : {false, true}) {
        const TracerResult* q = m.find("rtt");
        packet_total += std::max(0.0, seconds("packet", shadow));
        wide_total += std::max(0.0, seconds(wide, shadow));
        rtt_total += std::max(0.0, seconds("rtt", shadow));
        t.rows.push_back(
            {shadow ? "shadow" : "primary", format_count(shadow ? m.shadow_rays : m.primary_rays),
             ms(seconds("packet", shadow)), ms(seconds(wide, shadow)), ms(seconds("rtt", shadow)),
             q ? format_count((shadow ? q->shadow : q->primary).stats.traced) : "-",
             format_ratio(speedup(m, "rtt", "packet", shadow, clock)),
             format_ratio(speedup(m, "rtt", wide, shadow, clock))});
    }
    const double combined = rtt_total > 0 ? packet_total / rtt_total : 0.0;
    t.rows.push_back({"both", format_count(m.primary_rays + m.shadow_rays), format_ms(packet_total),
                      format_ms(wide_total), rtt_total > 0 ? format_ms(rtt_total) : "-", "",
                      format_ratio(combined),
                      format_ratio(rtt_total > 0 ? wide_total / rtt_total : 0.0)});
    t.notes.push_back("The paper (section 4): room at 2048x1560 with 6x6 antialiasing, RTT " +
                      format_ratio(paper::room_2048_aa6_speedup) + " faster than SIMD packets.");
    for (const std::string& n : agreement_notes(r.measurements)) t.notes.push_back(n);
    print_table(config.log, t);
    r.tables.push_back(t);
    r.extra = {{"combined_speedup", combined}, {"paper_speedup", paper::room_2048_aa6_speedup}};

    const double sp = speedup(m, "rtt", "packet", false, clock);
    std::string line = name + " " + size_label(w, h) + " 6x6: rtt/packet " + format_ratio(sp) +
                       " primary, " + format_ratio(speedup(m, "rtt", "packet", true, clock)) +
                       " shadow, " + format_ratio(combined) + " both (paper " +
                       format_ratio(paper::room_2048_aa6_speedup) + "); " +
                       against_widest(m, clock);
    if (!config.quick() && name == "room")
        line += "; issue-5 target >= " + format_ratio(paper::target_speedup_hq) + ": primary " +
                verdict(sp, paper::target_speedup_hq) + ", both " +
                verdict(combined, paper::target_speedup_hq);
    r.findings.push_back(line);
    return r;
}

}  // namespace rtt::bench
