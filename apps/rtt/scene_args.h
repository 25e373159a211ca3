// Choosing and loading the scene of a subcommand: --mesh FILE, or --scene NAME|FILE (also given
// as the one positional argument).
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "rtt/math.h"
#include "rtt/scene.h"

namespace rtt::cli {

struct SceneArgs {
    std::string mesh;     ///< --mesh FILE
    std::string scene;    ///< --scene NAME | FILE
    std::string input;    ///< The positional argument, meaning --scene.
    bool strict = false;  ///< --strict: refuse a file that needed repairs (Scene::warnings).

    /// What names the scene (whichever is given), for file names and messages.
    const std::string& source() const {
        return !mesh.empty() ? mesh : !scene.empty() ? scene : input;
    }
};

/// Adds --mesh, --scene (mutually exclusive) and a positional argument meaning --scene to a
/// subcommand.
void add_scene_options(CLI::App& command, SceneArgs& args);

struct LoadedScene {
    Scene scene;
    bool from_mesh = false;  ///< --mesh: geometry only (grey material, no lights, no camera).
    std::string label;       ///< Scene name or file, for messages and statistics.
};

/// Loads what the arguments name. A --mesh keeps the geometry and the file's materials (grey
/// where it has none); its lights and cameras are dropped. A --scene is a
/// built-in scene's name or a scene file (JSON, or any mesh format assimp reads). Throws
/// rtt::Error unless exactly one of the three is given, or when the scene is unknown or the
/// file is bad, or (--strict) was read with repairs.
/// The importer's warnings (skipped or repaired input, Scene::warnings) go to stderr, at most
/// a few lines.
LoadedScene load_scene(const SceneArgs& args);
/// The same without printing the warnings.
LoadedScene load_scene_quietly(const SceneArgs& args);
/// The importer's warnings on stderr: a few lines, then how many more there were.
void print_warnings(const Scene& scene);

/// The camera a command starts from: `given` (--camera) if any, else the scene's own (not for a
/// --mesh), else one looking at the scene's bounds from a diagonal.
Camera starting_camera(const LoadedScene& loaded, const std::optional<Camera>& given);

/// Puts the lights of --light (omni lights at `positions`) in place of the scene's; a scene
/// left without lights gets one omni light at `eye`. Returns true in that case: the light is
/// then "lit from the eye", and the caller moves it with the camera (make_point_light).
bool set_up_lights(Scene& scene, const std::vector<Vec3f>& positions, const Vec3f& eye);

}  // namespace rtt::cli
