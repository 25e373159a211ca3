#include "tree_args.h"

#include "rtt/kd_tree_file.h"

namespace rtt::cli {

void add_tree_options(CLI::App& command, TreeArgs& args) {
    auto* save = command.add_option(
        "--save-tree", args.save,
        "Write the kd-tree to FILE after building it, for --load-tree in later runs");
    command
        .add_option("--load-tree", args.load,
                    "Load the kd-tree from FILE (written by --save-tree for the same mesh) "
                    "instead of building it")
        ->excludes(save);
}

KdTree make_tree(const TreeArgs& args, const Scene& scene) {
    if (!args.load.empty()) return load_kd_tree(args.load, scene);
    KdTree tree = build_kdtree(scene);
    if (!args.save.empty()) save_kd_tree(args.save, tree, scene);
    return tree;
}

}  // namespace rtt::cli
