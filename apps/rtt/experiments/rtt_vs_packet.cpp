// The comparison `rtt` prints after its default render: RTT against the paper's baseline on the
// same rays, small enough to take a few seconds.
#include "experiments/experiment_common.h"
#include "experiments/paper_data.h"

namespace rtt::bench {

void print_rtt_vs_packet(std::FILE* out, const std::string& scene_name) {
    if (!has_tracer("rtt")) {
        std::fprintf(out, "rtt vs packet: this build has no 'rtt' tracer\n");
        return;
    }
    // The paper's Table 1 setting, then a quarter of its pixels with 4x4 antialiasing (4x the
    // rays): at one sample per pixel a 4x4 tile is one 16-wide packet, with antialiasing a shaft
    // holds many packets' worth of rays, which is where RTT pays (docs/benchmarks.md).
    struct Setting {
        int width, height, aa;
    };
    constexpr Setting settings[] = {{640, 480, 1}, {320, 240, 4}};
    BenchConfig config;
    config.log = out;
    std::fprintf(out, "\nRTT vs 4-wide SIMD packets on %s, same rays, 1 thread:\n",
                 scene_name.c_str());
    std::fflush(out);
    const BenchScene scene = load_bench_scene(scene_name);
    const std::string wide = detail::widest_packet();
    const std::vector<NamedTracer> tracers =
        make_tracers(scene, detail::available({"packet", wide, "rtt"}));
    std::vector<Measurement> measured;
    for (const Setting& s : settings)
        measured.push_back(
            detail::run_measurement(config, scene, tracers, s.width, s.height, s.aa, 1));

    TextTable t;
    t.header = {"rays",       "image",    "count",    "packet ms", "rtt ms",
                "rtt traced", "avg list", "speed-up", "paper",     "rtt/" + wide};
    const paper::Table1Column* p = paper::table1_column(scene_name);
    for (size_t i = 0; i < measured.size(); ++i) {
        const Measurement& m = measured[i];
        const Setting& s = settings[i];
        const std::string image = detail::size_label(s.width, s.height) + " " +
                                  std::to_string(s.aa) + "x" + std::to_string(s.aa);
        // The paper's Table 1 is at 640x480 without antialiasing only.
        const bool paper_setting = p && s.aa == 1 && s.width == 640 && s.height == 480;
        for (bool shadow : {false, true}) {
            const KindResult& a = shadow ? m.find("packet")->shadow : m.find("packet")->primary;
            const KindResult& b = shadow ? m.find("rtt")->shadow : m.find("rtt")->primary;
            t.rows.push_back(
                {shadow ? "shadow" : "primary", image, format_count(a.rays),
                 format_ms(a.seconds(config.clock)), format_ms(b.seconds(config.clock)),
                 format_count(b.stats.traced), format_fixed(b.rtt.avg_relevant(), 3),
                 format_ratio(speedup(m, "rtt", "packet", shadow, config.clock)),
                 paper_setting ? format_ratio(shadow ? p->shadow_speedup() : p->primary_speedup())
                               : "-",
                 format_ratio(speedup(m, "rtt", wide, shadow, config.clock))});
        }
    }
    t.notes.push_back("Times: CPU time of the tracing thread, sum over bands of the median of " +
                      std::to_string(measured.front().repetitions) +
                      " interleaved repetitions; paper = Table 1 (2004); rtt/" + wide +
                      ": against the widest packets, RTT's own fallback.");
    for (const std::string& n : agreement_notes(measured)) t.notes.push_back(n);
    t.notes.push_back("All experiments: rtt bench --help");
    print_table(out, t);
}

}  // namespace rtt::bench
