// `rtt bench`: the paper's experiments (section 4) and Embree, on the same rays, one command each.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <sstream>

#include "commands.h"
#include "experiments/experiments.h"
#include "experiments/results_doc.h"
#include "experiments/workload.h"
#include "mpi_render.h"
#include "rtt/error.h"
#include "rtt/io.h"
#include "tree_args.h"

namespace rtt::cli {
namespace {

struct BenchArgs {
    bool quick = false;
    bool long_run = false;
    int threads = 1;
    int repetitions = 0;  // 0 = mode default
    int region = 0;       // 0 = RenderOptions' default per K
    std::string scenes = "room,office,plants";
    std::string out_dir = "bench-results";
    std::string json;
    std::string markdown;
    std::string clock = "cpu";
    std::string save_trees, load_trees;  // folders of <scene>.kdtree files
    std::string command_line;
};

std::vector<std::string> split_list(const std::string& text) {
    std::vector<std::string> out;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ','))
        if (!item.empty()) out.push_back(item);
    if (out.empty())
        throw Error("--scenes: expected a comma-separated list of scenes, got '" + text + "'");
    return out;
}

using Experiment = bench::ExperimentResult (*)(const bench::BenchConfig&, bench::SceneCache&);

/// The experiments one after the other in this process.
void run_here(const bench::BenchConfig& config, bench::SceneCache& scenes,
              const std::vector<Experiment>& experiments, bench::ResultsDocument& doc,
              const std::function<void()>& save, std::chrono::steady_clock::time_point start) {
    for (size_t i = 0; i < experiments.size(); ++i) {
        if (experiments.size() > 1) {
            std::printf(
                "\nrtt bench: experiment %zu of %zu, %.0f s into the run\n", i + 1,
                experiments.size(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
            std::fflush(stdout);
        }
        doc.experiments.push_back(experiments[i](config, scenes));
        save();
    }
}

/// Under mpirun: each experiment runs whole on one rank (timed there), and rank 0 gathers the
/// results in the experiments' order, printing each one's log as it arrives. Plots and images
/// are written by the rank that ran the experiment (--out-dir: a shared folder on a cluster).
void run_distributed(const bench::BenchConfig& config, bench::SceneCache& scenes,
                     const std::vector<Experiment>& experiments, bench::ResultsDocument& doc,
                     const std::function<void()>& save) {
    std::vector<std::optional<bench::ExperimentResult>> results(experiments.size());
    std::vector<RankStats> ranks;
    // An experiment takes minutes: a rank is taken for hung only after an hour (or 10x the
    // slowest experiment so far).
    constexpr double bench_rank_timeout = 3600;
    distribute_items(
        experiments.size(),
        [&](size_t i) {
            // The experiment's tables go with its result, so that rank 0 prints them whole.
            char* text = nullptr;
            size_t length = 0;
            std::FILE* log = open_memstream(&text, &length);
            if (!log) throw Error("cannot buffer the experiment's log");
            bench::BenchConfig here = config;
            here.log = log;
            nlohmann::json j;
            try {
                j["result"] = bench::experiment_json(experiments[i](here, scenes));
            } catch (...) {
                std::fclose(log);
                std::free(text);
                throw;
            }
            std::fclose(log);
            j["log"] = std::string(text, length);
            std::free(text);
            j["rank"] = mpi_rank();
            const std::string bytes = j.dump();
            return std::vector<char>(bytes.begin(), bytes.end());
        },
        [&](size_t i, std::vector<char>& bytes) {
            const nlohmann::json j = nlohmann::json::parse(bytes.begin(), bytes.end());
            std::printf("\nrtt bench: experiment %zu of %zu, run on rank %d:\n%s", i + 1,
                        experiments.size(), j.at("rank").get<int>(),
                        j.at("log").get<std::string>().c_str());
            std::fflush(stdout);
            results[i] = bench::experiment_from_json(j.at("result"));
            // The document keeps the experiments' order: those finished so far, up to the
            // first one still running.
            doc.experiments.clear();
            for (const auto& r : results) {
                if (!r) break;
                doc.experiments.push_back(*r);
            }
            save();
        },
        &ranks, bench_rank_timeout);
    if (mpi_rank() != 0) return;
    doc.experiments.clear();
    for (const auto& r : results) doc.experiments.push_back(*r);
    save();
    for (const RankStats& r : ranks)
        std::printf("rank %d: %.1f s running experiments, %.1f s idle\n", r.rank, r.busy_seconds,
                    r.idle_seconds);
}

void run(const BenchArgs& args, const std::vector<Experiment>& experiments) {
    if (args.threads < 1) throw Error("--threads must be at least 1");
    if (args.repetitions < 0) throw Error("--reps must be at least 1");
    if (args.clock != "cpu" && args.clock != "wall") throw Error("--clock must be cpu or wall");
    if (args.quick && args.long_run) throw Error("--quick and --long exclude each other");
    bench::BenchConfig config;
    config.scenes = split_list(args.scenes);
    for (const std::string& s : config.scenes) bench::require_scene(s);
    config.threads = args.threads;
    config.region = args.region;
    config.mode = args.quick      ? bench::BenchMode::quick
                  : args.long_run ? bench::BenchMode::long_run
                                  : bench::BenchMode::full;
    config.repetitions = args.repetitions > 0 ? args.repetitions : args.quick ? 1 : 3;
    config.clock = args.clock == "cpu" ? bench::ClockKind::cpu : bench::ClockKind::wall;
    config.out_dir = args.out_dir;

    bench::ResultsDocument doc;
    doc.machine = bench::machine_info();
    doc.command = args.command_line;
    doc.mode = config.mode;
    doc.threads = config.threads;
    doc.repetitions = config.repetitions;
    doc.clock = config.clock;
    if (mpi_rank() == 0)
        std::printf(
            "rtt bench: %s mode, %d repetition(s), %d thread(s); %s, %s, commit %s, load %.2f\n",
            bench::mode_name(config.mode), config.repetitions, config.threads,
            doc.machine.cpu_model.c_str(), doc.machine.isa.c_str(), doc.machine.git_commit.c_str(),
            doc.machine.load_average);
    std::fflush(stdout);

    // The outputs are rewritten after every experiment, so that a long run stopped halfway
    // keeps what it measured (each file is replaced whole, never left half-written).
    const auto start = std::chrono::steady_clock::now();
    auto save = [&] {
        doc.seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        doc.load_end = bench::load_average();
        if (!args.json.empty()) bench::write_json_file(args.json, bench::results_json(doc));
        if (!args.markdown.empty()) {
            const std::string dir = std::filesystem::path(args.markdown).parent_path().string();
            const std::string md = bench::results_markdown(doc, dir.empty() ? "." : dir);
            write_file_atomically(args.markdown,
                                  [&](std::FILE* f) { std::fwrite(md.data(), 1, md.size(), f); });
        }
    };
    // --save-tree / --load-tree DIR: one file per scene, DIR/<scene name or file stem>.kdtree.
    const std::string tree_dir = args.load_trees.empty() ? args.save_trees : args.load_trees;
    bench::SceneCache scenes([&](const std::string& name, const Scene& scene) {
        const std::string file =
            (std::filesystem::path(tree_dir) / std::filesystem::path(name).stem()).string() +
            ".kdtree";
        if (!args.save_trees.empty()) std::filesystem::create_directories(tree_dir);
        return make_tree(
            TreeArgs{args.save_trees.empty() ? "" : file, args.load_trees.empty() ? "" : file},
            scene);
    });
    config.start = start;
    if (mpi_distributed()) {
        run_distributed(config, scenes, experiments, doc, save);
    } else {
        run_here(config, scenes, experiments, doc, save, start);
    }

    if (mpi_rank() != 0) return;
    std::printf("\nWhere we stand:\n");
    for (const bench::ExperimentResult& e : doc.experiments)
        for (const std::string& f : e.findings) std::printf("  %s: %s\n", e.id.c_str(), f.c_str());
    std::printf("rtt bench: %.1f minutes, load %.2f at the end\n", doc.seconds / 60.0,
                doc.load_end);
    for (const std::string* path : {&args.json, &args.markdown})
        if (!path->empty()) std::printf("wrote %s\n", path->c_str());
}

}  // namespace

void add_bench_command(CLI::App& app) {
    auto args = std::make_shared<BenchArgs>();
    CLI::App* bench = app.add_subcommand(
        "bench", "The paper's experiments (Table 1, Figures 5, 7, 8) and Embree, on the same rays");
    bench->require_subcommand(1);
    bench->footer(
        "Every tracer answers the same rays: the renderer's regions of 4x4-pixel tiles and, per\n"
        "region and\n"
        "light, the shadow segments from the packet tracer's hit points. Answers are checked\n"
        "against the 4-wide packet tracer before timing (mismatches printed). Timed: the median\n"
        "of --reps repetitions after a checking pass, tracers interleaved; 1 thread unless\n"
        "--threads; CPU time of the tracing thread (--clock wall for wall time; several threads\n"
        "always use wall time).\n"
        "Sizes: the paper's, except Figure 7 at 320x240 and Embree's K=4 at 512x384 in the\n"
        "default full mode (`rtt bench all`: 10-15 minutes on a 2-core machine); --long runs\n"
        "those at 640x480 and 1024x768 too (about half an hour); --quick is a 1-2 minute smoke\n"
        "run.");
    bench->add_flag("--quick", args->quick, "Smoke run: tiny images, 1 repetition");
    bench->add_flag("--long", args->long_run,
                    "Every experiment at the paper's / issue's exact size");
    bench
        ->add_option("--threads", args->threads,
                     "Tracing threads (default 1: the paper measures one core, and ratios of "
                     "tracers are steadiest on one; `rtt render` uses all cores)")
        ->capture_default_str();
    bench->add_option("--reps", args->repetitions, "Timed repetitions (default 3; 1 with --quick)");
    bench
        ->add_option("--region", args->region,
                     "Pixels per side of the tiles handed to the tracers, as `rtt render "
                     "--region` (0 = the renderer's default for each K)")
        ->capture_default_str();
    bench->add_option("--scenes", args->scenes, "Comma-separated built-in scenes or scene files")
        ->capture_default_str();
    bench->add_option("--out-dir", args->out_dir, "Folder for plots and images")
        ->capture_default_str();
    bench->add_option("--json", args->json, "Write every figure and the machine details as JSON");
    bench->add_option("--markdown", args->markdown,
                      "Write the results as Markdown (docs/RESULTS.md)");
    auto* save_trees =
        bench->add_option("--save-tree", args->save_trees,
                          "Write each scene's kd-tree to DIR/<scene>.kdtree after building it");
    bench
        ->add_option("--load-tree", args->load_trees,
                     "Load each scene's kd-tree from DIR/<scene>.kdtree (written by --save-tree) "
                     "instead of building it")
        ->excludes(save_trees);
    bench->add_option("--clock", args->clock, "Single-thread clock: cpu or wall")
        ->capture_default_str();

    struct Sub {
        const char* name;
        const char* help;
        std::vector<Experiment> experiments;
    };
    const Sub subs[] = {
        {"table1",
         "Table 1: packet vs rtt on each scene at 640x480, no antialiasing",
         {bench::run_table1}},
        {"fig7",
         "Figure 7: speed-up rtt/packet against antialiasing 1x1..6x6 (table + SVG)",
         {bench::run_fig7}},
        {"fig8",
         "Figure 8: speed-up against resolution 320x240..2048x1536 (table + SVG)",
         {bench::run_fig8}},
        {"hq",
         "Room at 2048x1536 with 6x6 antialiasing (the paper's 2.43x point)",
         {bench::run_hq}},
        {"fig5",
         "Figure 5: office and its RTT maps for primary and shadow rays (PNG)",
         {bench::run_fig5}},
        {"embree",
         "Embree beside packet, packet16, frustum, rtt and bvh at 1024x768, K=1 and 4, 1 thread "
         "and "
         "all cores",
         {bench::run_embree}},
        {"build",
         "kd-tree build beside Embree's BVH build, 1 thread and all cores (also in embree)",
         {bench::run_build}},
        {"answers",
         "ns per ray rtt answers from a list, K=1 and 4, beside the limit of an answer",
         {bench::run_answers}},
        {"rays",
         "Random and bounce rays, closest hit and visibility: every exact kind beside Embree's "
         "single rays and stream, 1 thread and all cores",
         {bench::run_rays}},
        {"all",
         "Everything above except build, answers and rays, in that order",
         {bench::run_table1, bench::run_fig7, bench::run_fig8, bench::run_hq, bench::run_fig5,
          bench::run_embree}},
    };
    for (const Sub& s : subs) {
        CLI::App* sub = bench->add_subcommand(s.name, s.help);
        sub->fallthrough();  // `rtt bench all --quick` and `rtt bench --quick all` alike
        const std::vector<Experiment> experiments = s.experiments;
        const std::string name = s.name;
        sub->callback([args, experiments, &app, name] {
            args->command_line = "rtt bench " + name;
            for (const CLI::Option* o : app.get_subcommand("bench")->get_options())
                if (o->count() > 0 && o->get_name() != "--help")
                    args->command_line +=
                        " " + o->get_name() +
                        (o->get_expected_min() > 0 ? " " + o->as<std::string>() : "");
            run(*args, experiments);
        });
    }
}

}  // namespace rtt::cli
