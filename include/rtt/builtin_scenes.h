// The built-in procedural test scenes, analogues of the paper's ROOM, OFFICE and PLANTS.
// Generated in code, deterministic: the same scene, bit for bit, on every machine.
#pragma once

#include <string>
#include <vector>

#include "rtt/scene.h"

namespace rtt {

struct BuiltinSceneInfo {
    std::string name;         ///< "room", "office", "plants", ...
    std::string description;  ///< One line for `rtt scenes`.
};

/// The built-in scenes, in a stable order.
std::vector<BuiltinSceneInfo> builtin_scenes();

/// True when `name` names a built-in scene.
bool is_builtin_scene(const std::string& name);

/// Generates a built-in scene, with its default camera and lights. Throws rtt::Error for an
/// unknown name.
Scene make_builtin_scene(const std::string& name);

}  // namespace rtt
