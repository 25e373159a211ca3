// assimp in a child process, so that a file which crashes it does not crash rtt.
//
// Why: fuzzing found files on which Debian's assimp 5.2 dereferences a null pointer (a
// COLLADA file with one mangled <param>, fuzz/corpus/fuzz_mesh/assimp_collada_crash.dae) within
// seconds; assimp's importers are many and not ours to fix. The import (assimp's ReadFile and
// rtt's conversion of its scene, import_assimp) runs in a fork()ed child, which sends the
// Scene back through a pipe. A child that dies becomes an rtt::Error naming the file.
#pragma once

#include <string>

#include "rtt/scene.h"

namespace rtt::detail {

/// import_assimp(path) run in a child process: the same Scene, or the same rtt::Error; a crash
/// or abnormal exit of the child throws rtt::Error "path: the importer crashed on this file
/// (signal N)". The child writes nothing of its own to stdout or stderr.
Scene import_assimp_isolated(const std::string& path);

/// The byte form a Scene crosses the pipe in (exposed for tests): every field of Scene.
std::string serialize_scene(const Scene& scene);
/// Inverse of serialize_scene; throws rtt::Error on malformed bytes.
Scene deserialize_scene(const std::string& bytes);

}  // namespace rtt::detail
