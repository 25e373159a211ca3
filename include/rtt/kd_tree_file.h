// Saving a built kd-tree and loading it back instead of building it again (`--save-tree`,
// `--load-tree`). The file is bound to its mesh and build configuration, and every size and
// index in it is checked on loading, so a stale, foreign or damaged file is refused, never used.
#pragma once

#include <cstdint>
#include <string>

#include "rtt/kdtree.h"
#include "rtt/scene.h"

namespace rtt {

/// Format version written into, and required in, kd-tree files.
inline constexpr uint32_t kd_tree_file_version = 1;

/// Hash of a mesh as a kd-tree file records it: the 36 vertex bytes of every triangle, in
/// triangle order (the vertices each triangle's indices name, not the index values).
uint64_t kd_mesh_hash(const Scene& scene);

/// Writes `tree`, built over `scene` with `config`, whole or not at all (a temporary file in
/// the same folder, then rename). Little-endian: a header (magic "RTTKDTRE", version, config,
/// triangle count, mesh hash, sizes, statistics), the nodes, the leaf
/// triangle lists and a checksum of everything before it. Throws rtt::Error naming `path`.
void save_kd_tree(const std::string& path, const KdTree& tree, const Scene& scene,
                  const KdBuildConfig& config = {});

/// Reads a tree saved by save_kd_tree for the same mesh (triangle count and kd_mesh_hash) and
/// the same config. Throws rtt::Error naming `path`, and allocates nothing beyond the file's
/// size, when the file is not a kd-tree file, has another version, was built for another mesh
/// or config, is truncated or fails its checksum, or holds a node or leaf range out of bounds
/// or a tree deeper than kd_max_depth: whatever the file holds, traversal of a returned tree
/// stays in bounds. The statistics are the saved ones; build_seconds is the load time.
KdTree load_kd_tree(const std::string& path, const Scene& scene, const KdBuildConfig& config = {});

}  // namespace rtt
