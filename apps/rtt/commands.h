// The subcommands of the `rtt` program. Each registers itself on the main CLI11 app; main.cpp
// only lists them, so a new subcommand is one file plus one line there.
#pragma once

#include <CLI/CLI.hpp>

namespace rtt::cli {

/// `rtt render`: render a mesh or scene to PNG, hit and shadow buffers, statistics.
void add_render_command(CLI::App& app);
/// `rtt info`: triangle count and kd-tree statistics of a mesh or scene.
void add_info_command(CLI::App& app);
/// `rtt scenes`: the built-in scenes with their descriptions.
void add_scenes_command(CLI::App& app);
/// `rtt bench`: the paper's experiments and Embree on the same rays (cmd_bench.cpp).
void add_bench_command(CLI::App& app);
/// `rtt view`: the interactive viewer (apps/rtt/view/; only in builds with GLFW).
void add_view_command(CLI::App& app);

/// `rtt` without arguments: the default main job (renders the built-in room to room.png and
/// prints the statistics).
void run_default_job();

}  // namespace rtt::cli
