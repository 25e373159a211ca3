// --save-tree FILE and --load-tree FILE: keeping a scene's kd-tree between runs.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "rtt/kdtree.h"
#include "rtt/scene.h"

namespace rtt::cli {

struct TreeArgs {
    std::string save;  ///< --save-tree FILE
    std::string load;  ///< --load-tree FILE
};

/// Adds --save-tree and --load-tree (mutually exclusive) to a subcommand.
void add_tree_options(CLI::App& command, TreeArgs& args);

/// The scene's kd-tree: loaded from --load-tree (refused with rtt::Error when the file does
/// not belong to this mesh or is damaged), else built, and written to --save-tree if given.
KdTree make_tree(const TreeArgs& args, const Scene& scene);

}  // namespace rtt::cli
