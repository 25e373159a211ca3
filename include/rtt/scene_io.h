// Loading scenes from files: any mesh or scene format assimp reads, and rtt's JSON scene files.
#pragma once

#include <string>

#include "rtt/scene.h"

namespace rtt {

/// Loads any format assimp reads (OBJ, PLY, OFF, STL, glTF/GLB, 3DS, COLLADA, ...), with the
/// cameras and lights the file carries. Triangle indices follow CONVENTIONS: file order, polygons
/// split as fans (v0 v1 v2), (v0 v2 v3), ... Meshes without materials get a default grey one.
/// The result is validated; throws rtt::Error (with the path) on any failure.
Scene load_mesh_file(const std::string& path);

/// Loads an rtt JSON scene file (schema: docs/scene-format.md). Mesh paths are relative to the
/// JSON file's folder. Throws rtt::Error with file:line context.
Scene load_scene_json(const std::string& path);

/// load_scene_json for *.json, load_mesh_file otherwise.
Scene load_scene_file(const std::string& path);

}  // namespace rtt
