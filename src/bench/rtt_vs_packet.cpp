// The comparison `rtt` prints after its default render: RTT against the paper's baseline on the
// same rays, small enough to take a few seconds.
#include "bench/experiment_common.h"
#include "bench/paper_data.h"

namespace rtt::bench {

void print_rtt_vs_packet(std::FILE* out, const std::string& scene_name) {
    if (!has_tracer("rtt")) {
        std::fprintf(out, "rtt vs packet: this build has no 'rtt' tracer\n");
        return;
    }
    constexpr int w = 640, h = 480;
    BenchConfig config;
    config.log = out;
    std::fprintf(out, "\nRTT vs 4-wide SIMD packets on %s, %dx%d, 1x1, same rays, 1 thread:\n",
                 scene_name.c_str(), w, h);
    std::fflush(out);
    const BenchScene scene = load_bench_scene(scene_name);
    const std::string wide = detail::widest_packet();
    const Measurement m = detail::run_measurement(
        config, scene, make_tracers(scene, detail::available({"packet", wide, "rtt"})), w, h, 1, 1);

    TextTable t;
    t.header = {"rays",     "count",    "packet ms", "rtt ms", "rtt traced",
                "avg list", "speed-up", "paper",     "rtt/" + wide};
    const paper::Table1Column* p = paper::table1_column(scene_name);
    for (bool shadow : {false, true}) {
        const KindResult& a = shadow ? m.find("packet")->shadow : m.find("packet")->primary;
        const KindResult& b = shadow ? m.find("rtt")->shadow : m.find("rtt")->primary;
        t.rows.push_back(
            {shadow ? "shadow" : "primary", format_count(a.rays),
             format_ms(a.seconds(config.clock)), format_ms(b.seconds(config.clock)),
             format_count(b.stats.traced), format_fixed(b.stats.avg_relevant(), 3),
             format_ratio(speedup(m, "rtt", "packet", shadow, config.clock)),
             p ? format_ratio(shadow ? p->shadow_speedup() : p->primary_speedup()) : "-",
             format_ratio(speedup(m, "rtt", wide, shadow, config.clock))});
    }
    t.notes.push_back("Times: CPU time of the tracing thread, sum over bands of the median of " +
                      std::to_string(m.repetitions) +
                      " interleaved repetitions; paper = Table 1 (2004); rtt/" + wide +
                      ": against the widest packets, RTT's own fallback.");
    for (const std::string& n : agreement_notes({m})) t.notes.push_back(n);
    t.notes.push_back("All experiments: rtt bench --help");
    print_table(out, t);
}

}  // namespace rtt::bench
