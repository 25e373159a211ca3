#include "scene_args.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <vector>

#include "rtt/builtin_scenes.h"
#include "rtt/camera.h"
#include "rtt/error.h"
#include "rtt/render.h"
#include "rtt/scene_io.h"

namespace rtt::cli {

void add_scene_options(CLI::App& command, SceneArgs& args) {
    auto* mesh = command.add_option(
        "--mesh", args.mesh,
        "Mesh file in any format assimp reads (OBJ, PLY, OFF, STL, glTF, ...), with "
        "its materials; the default camera and light");
    auto* scene = command.add_option(
        "--scene", args.scene,
        "Built-in scene name (see `rtt scenes`), JSON scene file, or a mesh file with its own "
        "materials, lights and cameras");
    mesh->excludes(scene);
    // `rtt render bunny.obj`, as other renderers take their input: the file's own materials,
    // lights and camera are kept, as with --scene. Not declared exclusive of the two options:
    // after a mistyped option (`--sise 8x8`) its value lands here, and CLI11 would then report
    // the exclusion instead of the typo; load_scene refuses two scenes instead.
    command.add_option(
        "input", args.input,
        "The same as --scene: a built-in scene name or a scene file (JSON or any mesh format)");
    command.add_flag("--strict", args.strict,
                     "Refuse a file that needed repairs (unknown header lines, unnamed materials, "
                     "empty parts, triangles dropped; docs/robustness.md, \"Reading policy\")");
}

void print_warnings(const Scene& scene) {
    constexpr size_t shown = 5;
    for (size_t i = 0; i < scene.warnings.size() && i < shown; ++i)
        std::fprintf(stderr, "rtt: warning: %s\n", scene.warnings[i].c_str());
    if (scene.warning_count > shown)
        std::fprintf(stderr, "rtt: warning: ... and %zu more\n", scene.warning_count - shown);
}

LoadedScene load_scene(const SceneArgs& args) {
    LoadedScene out = load_scene_quietly(args);
    print_warnings(out.scene);
    return out;
}

namespace {

/// --strict: a file read with repairs is refused, naming the first repair and the count.
void refuse_repairs_if_strict(const SceneArgs& args, const LoadedScene& loaded) {
    const Scene& s = loaded.scene;
    if (!args.strict || s.warning_count == 0) return;
    // The warnings name the file.
    throw Error(s.warnings.front() + " (refused under --strict" +
                (s.warning_count > 1 ? "; " + std::to_string(s.warning_count - 1) + " more repairs"
                                     : std::string()) +
                ")");
}

}  // namespace

LoadedScene load_scene_quietly(const SceneArgs& args) {
    const int given = int(!args.mesh.empty()) + int(!args.scene.empty()) + int(!args.input.empty());
    if (given != 1)
        throw Error(
            "give exactly one scene: --mesh FILE, --scene NAME|FILE or the file or name "
            "alone");
    if (!args.input.empty())
        return load_scene_quietly(SceneArgs{.scene = args.input, .strict = args.strict});
    LoadedScene out;
    if (!args.mesh.empty()) {
        out.scene = load_mesh_file(args.mesh);
        out.from_mesh = true;
        out.label = args.mesh;
        // The file's materials and colours stay (a file without any has the default grey);
        // its lights and camera do not: --mesh frames the geometry with the default camera and
        // a light at the eye (CONVENTIONS), which hit and shadow buffers of outside checks
        // rely on. `rtt render FILE` (--scene FILE) keeps them too.
        out.scene.lights.clear();
        out.scene.camera.reset();
        refuse_repairs_if_strict(args, out);
        return out;
    }
    out.label = args.scene;
    if (is_builtin_scene(args.scene)) {
        out.scene = make_builtin_scene(args.scene);
    } else if (std::filesystem::exists(args.scene) || args.scene.find('/') != std::string::npos ||
               args.scene.find('.') != std::string::npos) {
        out.scene = load_scene_file(args.scene);
    } else {
        std::string names;
        for (const BuiltinSceneInfo& s : builtin_scenes())
            names += (names.empty() ? "" : ", ") + s.name;
        throw Error("unknown scene '" + args.scene + "' (built-in scenes: " + names +
                    "; or give a JSON scene file)");
    }
    refuse_repairs_if_strict(args, out);
    return out;
}

Camera starting_camera(const LoadedScene& loaded, const std::optional<Camera>& given) {
    if (given) return *given;
    if (loaded.scene.camera && !loaded.from_mesh) return *loaded.scene.camera;
    return default_camera_for(loaded.scene.bounds());
}

bool set_up_lights(Scene& scene, const std::vector<Vec3f>& positions, const Vec3f& eye) {
    const Bbox3f bounds = scene.bounds();
    if (!positions.empty()) {
        scene.lights.clear();
        for (const Vec3f& p : positions)
            scene.lights.push_back(make_point_light(p, bounds, positions.size()));
        return false;
    }
    if (!scene.lights.empty()) return false;
    scene.lights.push_back(make_point_light(eye, bounds, 1));
    return true;
}

}  // namespace rtt::cli
