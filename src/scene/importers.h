// The mesh importers behind load_mesh_file (src/scene/scene_file.cpp picks one by extension).
// Each returns an unvalidated Scene named after the path; load_mesh_file validates it.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "rtt/scene.h"

namespace rtt::detail {

/// Any format assimp reads. Throws rtt::Error "path: message" on failure.
Scene import_assimp(const std::string& path);

/// Wavefront OBJ (+ MTL) with correctly rounded coordinates (std::from_chars); see
/// docs/scene-format.md for why OBJ does not go through assimp. Errors carry "path:line:".
Scene import_obj(const std::string& path);

/// Object File Format (OFF, COFF, NOFF, CNOFF; ASCII), for the same reasons as OBJ, and because
/// assimp 5.2's OFF reader clamps out-of-range indices and drops faces after a comment line.
Scene import_off(const std::string& path);

/// A PLY triangle mesh (vertex and face elements only; x, y, z and perhaps normals; no colours;
/// binary, or ASCII with one record per line) read without assimp; nullopt for any other PLY,
/// which import_assimp reads.
std::optional<Scene> import_ply_native(const std::string& path);

/// What check_ply_structure repaired: a warning per repair, and when there was one the file's
/// text with the repairs (unknown header lines made comments), for assimp to read instead.
struct PlyCheck {
    std::vector<std::string> warnings;
    std::string repaired;
};

/// Throws rtt::Error when the PLY file at `path` is shorter than its header says (ASCII or
/// binary) or its header is malformed; assimp 5.2 reads such files without complaint, and
/// loops forever on some malformed headers. A header line that is no PLY keyword is repaired.
PlyCheck check_ply_structure(const std::string& path);

/// Appends the fan triangulation of polygon `poly` (n >= 3 vertex indices) to `out`:
/// (v0 v1 v2), (v0 v2 v3), ..., in that order (CONVENTIONS).
template <typename Index>
void append_fan(const Index* poly, size_t n, std::vector<TriangleIndices>& out) {
    for (size_t k = 1; k + 1 < n; ++k)
        out.push_back({uint32_t(poly[0]), uint32_t(poly[k]), uint32_t(poly[k + 1])});
}

/// `text` with every control character (newlines included) replaced by a space and the ends
/// trimmed, so third-party messages fit rtt's one-line errors.
std::string one_line(const std::string& text);

/// Throws rtt::Error "path: ..." unless `path` is an existing, readable, non-empty regular file
/// (so every importer reports these cases the same way).
void require_readable_file(const std::string& path);

/// Lower-case extension without the dot ("OBJ" -> "obj"); empty when there is none.
std::string lower_extension(const std::string& path);

}  // namespace rtt::detail
