// Figure 5: the office scene and where RTT answered its rays, written by the renderer itself
// (AnswerMaps primary and shadow_light, the maps behind `rtt render
// --rtt-map-primary / --rtt-map-shadow`).
#include "experiments/experiment_common.h"
#include "rtt/io.h"
#include "rtt/render.h"

namespace rtt::bench {

using namespace detail;

namespace {

/// The light nearest the centre of the scene's bounds: the paper shows "one of the light
/// sources"; a central one shows both lit and shadowed regions of the room.
int central_light(const Scene& scene) {
    const Vec3f c = scene.bounds().center();
    int best = 0;
    float best_d = pos_inf;
    for (size_t l = 0; l < scene.lights.size(); ++l) {
        const Vec3f d = scene.lights[l].position - c;
        if (dot(d, d) < best_d) best_d = dot(d, d), best = int(l);
    }
    return best;
}

}  // namespace

ExperimentResult run_fig5(const BenchConfig& config, SceneCache& scenes) {
    const int w = config.quick() ? 160 : 640, h = config.quick() ? 120 : 480;
    ExperimentResult r;
    r.id = "fig5";
    r.title = "Figure 5: RTT on office at " + size_label(w, h);
    std::fprintf(config.log, "\n== %s\n", r.title.c_str());
    if (!has_tracer("rtt")) {
        r.findings.push_back("no 'rtt' tracer in this build: no Figure 5 maps");
        std::fprintf(config.log, "  %s\n", r.findings.back().c_str());
        return r;
    }
    const BenchScene& scene = scenes.get("office");
    const auto tracer = make_tracer("rtt", scene.scene, scene.tree);
    RenderOptions options;
    options.camera = scene.camera;
    options.width = w;
    options.height = h;
    options.threads = config.threads;
    AnswerMaps maps;
    maps.primary = true;
    maps.shadow_light = scene.scene.lights.empty() ? -1 : central_light(scene.scene);
    const RenderResult result = render(scene.scene, *tracer, options, maps);

    const std::string a = output_path(config, "fig5a_office.png");
    const std::string b = output_path(config, "fig5b_office_primary.png");
    write_png(a, w, h, 3, encode_srgb8(result.pixels));
    write_png(b, w, h, 1, result.primary_map);
    r.files = {a, b};
    if (maps.shadow_light >= 0) {
        const std::string c = output_path(
            config, "fig5c_office_shadow_light" + std::to_string(maps.shadow_light) + ".png");
        write_png(c, w, h, 1, result.shadow_map);
        r.files.push_back(c);
    }
    for (const std::string& f : r.files) std::fprintf(config.log, "  wrote %s\n", f.c_str());

    const KindStats& p = result.stats.primary;
    const KindStats& s = result.stats.shadow;
    auto percent = [](uint64_t part, uint64_t whole) {
        return whole ? format_fixed(100.0 * double(part) / double(whole), 1) + " %"
                     : std::string("-");
    };
    TextTable t;
    t.title = "Figure 5 (office, " + size_label(w, h) +
              ", all lights): rays RTT answered without traversal";
    t.header = {"rays", "asked", "answered by RTT", "traced", "avg relevant"};
    t.rows.push_back({"primary", format_count(p.trace.rays), percent(p.rtt.answered, p.trace.rays),
                      format_count(p.trace.traced), format_fixed(p.rtt.avg_relevant(), 3)});
    t.rows.push_back({"shadow", format_count(s.trace.rays), percent(s.rtt.answered, s.trace.rays),
                      format_count(s.trace.traced), format_fixed(s.rtt.avg_relevant(), 3)});
    t.notes.push_back("(b) white: answered by RTT, black: traced; (c) light " +
                      std::to_string(maps.shadow_light) +
                      ": white empty relevant list, grey tested against the list, black traced.");
    print_table(config.log, t);
    r.tables.push_back(t);
    r.findings.push_back("office " + size_label(w, h) + ": RTT answered " +
                         percent(p.rtt.answered, p.trace.rays) + " of primary and " +
                         percent(s.rtt.answered, s.trace.rays) + " of shadow rays");
    return r;
}

}  // namespace rtt::bench
