// `rtt scenes`: the built-in procedural scenes.
#include <cstdio>

#include "commands.h"
#include "rtt/builtin_scenes.h"

namespace rtt::cli {

void add_scenes_command(CLI::App& app) {
    CLI::App* cmd =
        app.add_subcommand("scenes", "List the built-in scenes (use with --scene NAME)");
    cmd->callback([] {
        for (const BuiltinSceneInfo& s : builtin_scenes())
            std::printf("%-10s %s\n", s.name.c_str(), s.description.c_str());
    });
}

}  // namespace rtt::cli
