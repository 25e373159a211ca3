// The kd-tree build beside Embree's BVH build (issue 16): wall seconds on one thread and on all
// cores, the builds alternating on the same scene, and the tree each kd-tree build gives; also
// what rtt's tracer sets up on a built tree and the bvh kind's own BVH (the first image's parts).
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <memory>

#include "experiments/experiment_common.h"
#include "trace/trace_embree.h"

namespace rtt::bench {

using namespace detail;

namespace {

double median_of(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty()      ? 0.0
           : v.size() % 2 ? v[v.size() / 2]
                          : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

struct BuildTimes {
    double kd_seconds = 0, bvh_seconds = -1;  ///< Medians; bvh -1 without Embree.
    double bvh_medium_seconds = -1;           ///< Embree's MEDIUM build (its default).
    double rtt_setup_seconds = 0;  ///< make_bench_tracer("rtt") on a built tree (plane ids, BVH).
    double our_bvh_seconds = 0;    ///< make_tracer("bvh"): the bvh kind's BVH.
    double our_bvh_high_seconds = 0;  ///< make_tracer("bvh-high"): with spatial splits.
    KdStats kd;                       ///< The last kd-tree built.
};

/// Wall seconds of make_bench_tracer(kind, ...).
double setup_seconds(const std::string& kind, const BenchScene& scene, const KdTree& tree) {
    const auto start = std::chrono::steady_clock::now();
    const std::unique_ptr<Tracer> tracer = make_bench_tracer(kind, scene.scene, tree);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Median build seconds of our kd-tree and of Embree's BVH with `threads` oneTBB threads,
/// alternating. The scene's own kd-tree, unless it was loaded from a file (`--load-tree`: its
/// build phases are zero), was built on all cores: with all cores it is the first sample.
BuildTimes build_times(const BenchScene& scene, int threads, int repetitions) {
    std::vector<double> kd, bvh, bvh_medium, rtt_setup, our_bvh, our_bvh_high;
    BuildTimes out;
    out.kd = scene.tree.stats;
    const bool built_here = scene.tree.stats.tree_seconds > 0.0;
    if (threads == tbb::info::default_concurrency() && built_here)
        kd.push_back(scene.tree.stats.build_seconds);
    tbb::task_arena arena(threads);
    arena.execute([&] {
        for (int r = 0; r < repetitions; ++r) {
            if (int(kd.size()) < repetitions) {
                out.kd = build_kdtree(scene.scene).stats;
                kd.push_back(out.kd.build_seconds);
            }
            rtt_setup.push_back(setup_seconds("rtt", scene, scene.tree));
            our_bvh.push_back(setup_seconds("bvh", scene, KdTree{}));
            our_bvh_high.push_back(setup_seconds("bvh-high", scene, KdTree{}));
            if (has_tracer("embree")) {
                bvh.push_back(
                    embree_build_seconds(*make_tracer("embree", scene.scene, scene.tree)));
                bvh_medium.push_back(
                    embree_build_seconds(*make_tracer("embree-medium", scene.scene, scene.tree)));
            }
        }
    });
    out.kd_seconds = median_of(kd);
    out.bvh_seconds = bvh.empty() ? -1.0 : median_of(bvh);
    out.bvh_medium_seconds = bvh_medium.empty() ? -1.0 : median_of(bvh_medium);
    out.rtt_setup_seconds = median_of(rtt_setup);
    out.our_bvh_seconds = median_of(our_bvh);
    out.our_bvh_high_seconds = median_of(our_bvh_high);
    return out;
}

}  // namespace

void add_build_table(const BenchConfig& config, SceneCache& scenes, ExperimentResult& r) {
    const int all = std::max(1, tbb::info::default_concurrency());
    std::vector<int> thread_counts{1};
    if (all > 1) thread_counts.push_back(all);

    TextTable builds;
    builds.title = "Build seconds (wall, median of " + std::to_string(config.repetitions) +
                   "): our SAH kd-tree vs Embree's BVH, quality HIGH and MEDIUM (its default)";
    // Quick mode times the first scene's builds only (a 1-thread kd-tree of plants takes ~1 s).
    const std::vector<std::string> build_scenes =
        config.quick() ? std::vector<std::string>(config.scenes.begin(), config.scenes.begin() + 1)
                       : config.scenes;
    builds.header = {"scene", "triangles"};
    for (int threads : thread_counts) {
        builds.header.push_back("kd-tree, " + std::to_string(threads) + "t");
        builds.header.push_back("Embree HIGH, " + std::to_string(threads) + "t");
        builds.header.push_back("Embree MEDIUM, " + std::to_string(threads) + "t");
        builds.header.push_back("kd/HIGH, " + std::to_string(threads) + "t");
        builds.header.push_back("kd/MEDIUM, " + std::to_string(threads) + "t");
        builds.header.push_back("rtt setup, " + std::to_string(threads) + "t");
        builds.header.push_back("bvh's BVH, " + std::to_string(threads) + "t");
        builds.header.push_back("bvh-high's, " + std::to_string(threads) + "t");
    }
    builds.header.insert(builds.header.end(), {"kd nodes", "kd references", "kd SAH cost"});
    nlohmann::json build_json = nlohmann::json::array();
    for (const std::string& name : build_scenes) {
        const BenchScene& scene = scenes.get(name);
        std::vector<std::string> row{name, format_count(scene.scene.triangle_count())};
        KdStats tree;
        for (int threads : thread_counts) {
            const BuildTimes t = build_times(scene, threads, config.repetitions);
            tree = t.kd;
            row.push_back(format_fixed(t.kd_seconds, 3));
            row.push_back(t.bvh_seconds >= 0 ? format_fixed(t.bvh_seconds, 3) : "-");
            row.push_back(t.bvh_medium_seconds >= 0 ? format_fixed(t.bvh_medium_seconds, 3) : "-");
            row.push_back(t.bvh_seconds > 0 ? format_ratio(t.kd_seconds / t.bvh_seconds) : "-");
            row.push_back(
                t.bvh_medium_seconds > 0 ? format_ratio(t.kd_seconds / t.bvh_medium_seconds) : "-");
            row.push_back(format_fixed(t.rtt_setup_seconds, 3));
            row.push_back(format_fixed(t.our_bvh_seconds, 3));
            row.push_back(format_fixed(t.our_bvh_high_seconds, 3));
            if (t.bvh_seconds > 0)
                r.findings.push_back(
                    name + ", " + std::to_string(threads) + " thread(s): kd-tree build " +
                    format_ratio(t.kd_seconds / t.bvh_seconds) + " of Embree's HIGH build (" +
                    (t.kd_seconds <= t.bvh_seconds ? "at or below" : "above") + " it), " +
                    format_ratio(t.kd_seconds / t.bvh_medium_seconds) + " of its MEDIUM build");
            build_json.push_back({{"scene", name},
                                  {"threads", threads},
                                  {"kdtree_s", t.kd_seconds},
                                  {"embree_bvh_s", t.bvh_seconds},
                                  {"embree_bvh_medium_s", t.bvh_medium_seconds},
                                  {"rtt_setup_s", t.rtt_setup_seconds},
                                  {"bvh_s", t.our_bvh_seconds},
                                  {"bvh_high_s", t.our_bvh_high_seconds}});
        }
        row.push_back(format_count(tree.nodes));
        row.push_back(format_count(tree.triangle_references));
        row.push_back(format_fixed(tree.sah_cost, 2));
        builds.rows.push_back(row);
    }
    if (!has_tracer("embree"))
        builds.notes.push_back("This build has no Embree: the Embree columns are missing.");
    print_table(config.log, builds);
    r.tables.push_back(builds);
    r.extra["builds"] = build_json;
}

ExperimentResult run_build(const BenchConfig& config, SceneCache& scenes) {
    ExperimentResult r;
    r.id = "build";
    r.title = "kd-tree build beside Embree's BVH build, 1 thread and all cores";
    std::fprintf(config.log, "\n== %s\n", r.title.c_str());
    add_build_table(config, scenes, r);
    return r;
}

}  // namespace rtt::bench
