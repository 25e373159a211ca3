// `rtt info`: what the kd-tree of a mesh or scene looks like.
#include <cstdio>
#include <memory>

#include "commands.h"
#include "rtt/kdtree.h"
#include "scene_args.h"
#include "stats_report.h"
#include "tree_args.h"

namespace rtt::cli {

void add_info_command(CLI::App& app) {
    auto args = std::make_shared<SceneArgs>();
    auto tree_args = std::make_shared<TreeArgs>();
    CLI::App* cmd =
        app.add_subcommand("info", "Triangle count and SAH kd-tree statistics of a mesh or scene");
    add_scene_options(*cmd, *args);
    add_tree_options(*cmd, *tree_args);
    cmd->callback([args, tree_args] {
        const LoadedScene loaded = load_scene(*args);
        const KdTree tree = make_tree(*tree_args, loaded.scene);
        const KdStats& s = tree.stats;
        std::printf("scene                         %s\n", loaded.label.c_str());
        std::printf("triangles                     %zu\n", s.triangles);
        std::printf("lights                        %zu\n", loaded.scene.lights.size());
        std::printf("kd-tree nodes                 %zu\n", s.nodes);
        std::printf("leaves                        %zu\n", s.leaves);
        std::printf("empty leaves                  %zu\n", s.empty_leaves);
        std::printf("max leaf depth                %d\n", s.max_depth);
        std::printf("average leaf depth            %.2f\n", s.avg_leaf_depth);
        std::printf("triangles per non-empty leaf  %.2f\n", s.avg_leaf_triangles);
        std::printf("triangle references           %zu\n", s.triangle_references);
        std::printf("SAH cost                      %.2f\n", s.sah_cost);
        if (tree_args->load.empty()) {
            std::printf("build time                    %.3f s\n", s.build_seconds);
            std::printf("build phases                  %s\n", kd_build_phases(s).c_str());
        } else {
            std::printf("load time                     %.3f s (%s)\n", s.build_seconds,
                        tree_args->load.c_str());
        }
        std::printf("memory                        %.2f MiB\n",
                    double(s.memory_bytes) / (1024.0 * 1024.0));
    });
}

}  // namespace rtt::cli
