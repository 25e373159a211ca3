#include "stats_report.h"

#include <nlohmann/json.hpp>

#include "rtt/io.h"

namespace rtt::cli {
namespace {

struct KindRow {
    const char* name;
    const KindStats* stats;
};

nlohmann::json kind_json(const KindStats& k) {
    const TraceStats& t = k.trace;
    const RttStats& r = k.rtt;
    nlohmann::json declined = nlohmann::json::object();
    for (const auto& [name, field] : declined_fields) declined[name] = r.*field;
    return {{"tiles", t.tiles},
            {"rtt_tiles", r.rtt_tiles},
            {"rays", t.rays},
            {"traced", t.traced},
            {"answered", r.answered},
            {"relevant_sum", r.relevant_sum},
            {"open_tiles", r.open_tiles},
            {"empty_tiles", r.empty_tiles},
            {"bvh_rays", r.bvh_rays},
            {"declined", declined},
            {"avg_relevant", r.avg_relevant()},
            {"seconds", k.seconds},
            {"fallback_seconds", r.fallback_seconds()},
            {"mrays_per_second", k.mrays_per_second()}};
}

}  // namespace

std::string kd_build_phases(const KdStats& s) {
    char line[256];
    std::snprintf(line, sizeof line,
                  "setup %.3f s, tree %.3f s (%zu binned nodes, %zu small subtrees), "
                  "layout %.3f s",
                  s.setup_seconds, s.tree_seconds, s.binned_nodes, s.small_subtrees,
                  s.layout_seconds);
    return line;
}

void print_rank_stats(std::FILE* out, const std::vector<RankStats>& ranks) {
    for (const RankStats& rank : ranks)
        std::fprintf(out, "rank %d: %llu tiles, %.3f s rendering, %.3f s idle\n", rank.rank,
                     (unsigned long long)rank.tiles, rank.busy_seconds, rank.idle_seconds);
}

void print_stats(std::FILE* out, const RenderJobResult& r) {
    const RenderResult& res = r.result;
    const RenderStats& s = res.stats;
    char kd[64] = "no kd-tree";
    if (r.kd_used)
        std::snprintf(kd, sizeof kd, "kd-tree %s in %.3f s", r.kd_loaded ? "loaded" : "built",
                      r.kd_build_seconds);
    std::fprintf(out,
                 "%s: %zu triangles, %s; tracer %s%s (set up in %.3f s); %dx%d, %dx%d AA, %d "
                 "threads\n",
                 r.scene_label.c_str(), r.triangles, kd, r.tracer.c_str(),
                 r.tracer_auto ? " (auto)" : "", r.tracer_build_seconds, res.width, res.height,
                 res.aa, res.aa, s.threads);
    if (r.input_warnings)
        std::fprintf(out, "input warnings: %zu (skipped or repaired input, first ones on stderr)\n",
                     r.input_warnings);
    if (r.kd_used && !r.kd_loaded)
        std::fprintf(out, "kd-tree build: %s\n", kd_build_phases(r.kd_stats).c_str());
    std::fprintf(out, "%-10s %9s %9s %12s %12s %12s %9s %9s %9s\n", "rays", "tiles", "rtt tiles",
                 "rays", "traced", "answered", "avg list", "seconds", "Mrays/s");
    const KindRow rows[] = {
        {"primary", &s.primary}, {"shadow", &s.shadow}, {"secondary", &s.secondary}};
    for (const KindRow& row : rows) {
        const TraceStats& t = row.stats->trace;
        const RttStats& r = row.stats->rtt;
        std::fprintf(out, "%-10s %9llu %9llu %12llu %12llu %12llu %9.2f %9.3f %9.2f\n", row.name,
                     (unsigned long long)t.tiles, (unsigned long long)r.rtt_tiles,
                     (unsigned long long)t.rays, (unsigned long long)t.traced,
                     (unsigned long long)r.answered, r.avg_relevant(), row.stats->seconds,
                     row.stats->mrays_per_second());
    }
    for (const KindRow& row : rows) {
        const RttStats& t = row.stats->rtt;
        if (t.declined() == 0) continue;
        std::fprintf(out,
                     "%s tiles declined (traced): %llu; no shaft %llu, R without end %llu, node "
                     "budget %llu, list full %llu, corners parted %llu\n",
                     row.name, (unsigned long long)t.declined(),
                     (unsigned long long)t.declined_shaft, (unsigned long long)t.declined_end,
                     (unsigned long long)t.declined_budget, (unsigned long long)t.declined_list,
                     (unsigned long long)t.declined_corners);
    }
    for (const KindRow& row : rows) {
        const RttStats& t = row.stats->rtt;
        if (t.answered == 0 && t.fallback_ns == 0) continue;
        const double fallback = t.fallback_seconds();
        std::fprintf(out,
                     "%s time split: %.3f s in the tiles' answers, corners and walks (%llu rays "
                     "answered); %.3f s in the fallback (%llu rays traced, corners included; "
                     "%llu of them through the BVH)\n",
                     row.name, row.stats->seconds - fallback, (unsigned long long)t.answered,
                     fallback, (unsigned long long)row.stats->trace.traced,
                     (unsigned long long)t.bvh_rays);
    }
    if (s.primary.rtt.open_tiles)
        std::fprintf(out,
                     "primary rtt tiles without an end (a corner missed): %llu, %llu of them "
                     "empty (all miss)\n",
                     (unsigned long long)s.primary.rtt.open_tiles,
                     (unsigned long long)s.primary.rtt.empty_tiles);
    print_rank_stats(out, r.ranks);
    std::fprintf(out,
                 "seconds = time inside the tracer summed over threads; Mrays/s = rays / seconds; "
                 "render wall time %.3f s\n",
                 s.wall_seconds);
}

void write_stats_json(const std::string& path, const RenderJob& job, const RenderJobResult& r) {
    const RenderResult& res = r.result;
    const RenderStats& s = res.stats;
    const nlohmann::json j = {
        {"scene", r.scene_label},
        {"triangles", r.triangles},
        {"input_warnings", r.input_warnings},
        {"tracer", r.tracer},
        {"tracer_auto", r.tracer_auto},
        {"width", res.width},
        {"height", res.height},
        {"aa", res.aa},
        {"threads", s.threads},
        {"max_depth", job.max_depth},
        {"kd_build_seconds", r.kd_build_seconds},
        {"kd_tree_loaded", r.kd_loaded},
        {"kd_tree_used", r.kd_used},
        {"tracer_build_seconds", r.tracer_build_seconds},
        {"kd_build_phases",
         {{"setup_seconds", r.kd_stats.setup_seconds},
          {"tree_seconds", r.kd_stats.tree_seconds},
          {"binned_nodes", r.kd_stats.binned_nodes},
          {"small_subtrees", r.kd_stats.small_subtrees},
          {"layout_seconds", r.kd_stats.layout_seconds}}},
        {"wall_seconds", s.wall_seconds},
        {"primary", kind_json(s.primary)},
        {"shadow", kind_json(s.shadow)},
        {"secondary", kind_json(s.secondary)},
        {"rays_by_depth", s.rays_by_depth},
    };
    const std::string text = j.dump(2) + "\n";
    write_file_atomically(path, [&](std::FILE* f) { std::fwrite(text.data(), 1, text.size(), f); });
}

}  // namespace rtt::cli
