// Entry points of scene_io.h: pick the importer from the file name, then validate the result.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <vector>

#include "rtt/error.h"
#include "rtt/scene_io.h"
#include "scene/assimp_sandbox.h"
#include "scene/importers.h"

namespace rtt {
namespace detail {

std::string one_line(const std::string& text) {
    std::string s = text;
    for (char& c : s)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
    const size_t b = s.find_first_not_of(' ');
    if (b == std::string::npos) return {};
    return s.substr(b, s.find_last_not_of(' ') - b + 1);
}

std::string lower_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    if (!ext.empty()) ext.erase(0, 1);
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

void require_readable_file(const std::string& path) {
    std::error_code ec;
    const auto st = std::filesystem::status(path, ec);
    if (st.type() == std::filesystem::file_type::not_found) throw Error(path, 0, "no such file");
    if (ec) throw Error(path, 0, "cannot access: " + ec.message());
    if (std::filesystem::is_directory(st)) throw Error(path, 0, "is a directory, not a file");
    // Devices and pipes could block or never end (/dev/zero).
    if (!std::filesystem::is_regular_file(st)) throw Error(path, 0, "not a regular file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path, 0, std::string("cannot open: ") + std::strerror(errno));
    if (in.peek() == std::ifstream::traits_type::eof()) throw Error(path, 0, "empty file");
}

}  // namespace detail

namespace {

/// Triangles on a NaN or infinite vertex cannot be drawn: they are dropped with one warning
/// (later triangles are numbered one less for each), and the vertices, which no triangle uses
/// any more, become copies of a used one so that the bounds are the triangles'. Throws when no
/// triangle is left.
void drop_non_finite_triangles(Scene& scene, const std::string& path) {
    std::vector<bool> bad(scene.vertices.size());
    size_t bad_count = 0;
    for (size_t v = 0; v < scene.vertices.size(); ++v)
        bad_count += bad[v] = !is_finite(scene.vertices[v]);
    if (bad_count == 0) return;
    size_t kept = 0;
    const size_t before = scene.triangles.size();
    for (size_t i = 0; i < before; ++i) {
        const TriangleIndices& t = scene.triangles[i];
        // Indices out of range are validate()'s to report.
        const auto on_bad = [&](uint32_t v) { return v < bad.size() && bad[v]; };
        if (on_bad(t[0]) || on_bad(t[1]) || on_bad(t[2])) continue;
        scene.triangles[kept] = t;
        if (i < scene.triangle_material.size())
            scene.triangle_material[kept] = scene.triangle_material[i];
        ++kept;
    }
    scene.triangles.resize(kept);
    scene.triangle_material.resize(std::min(scene.triangle_material.size(), kept));
    // The bad vertices stay (indices keep their meaning), moved to a finite point.
    const Vec3f used = kept ? scene.vertices[scene.triangles[0][0]] : Vec3f{0.f};
    for (size_t v = 0; v < scene.vertices.size(); ++v)
        if (bad[v]) scene.vertices[v] = used;
    scene.warn(path + ": " + std::to_string(bad_count) +
               " vertices with a NaN or infinite coordinate; the " + std::to_string(before - kept) +
               " triangles on them dropped" + (kept ? "" : ": nothing is left to render"));
}

}  // namespace

Scene load_mesh_file(const std::string& path) {
    detail::require_readable_file(path);
    const std::string ext = detail::lower_extension(path);
    std::optional<Scene> ply = ext == "ply" ? detail::import_ply_native(path) : std::nullopt;
    Scene scene = ext == "obj"   ? detail::import_obj(path)
                  : ext == "off" ? detail::import_off(path)
                  : ply          ? std::move(*ply)
                                 : detail::import_assimp_isolated(path);
    drop_non_finite_triangles(scene, path);
    validate(scene);
    // Zero-area triangles stay (a ray can still hit one edge-on, and indices must not move);
    // say so, since they often mean a broken export.
    size_t degenerate = 0, first = 0;
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        const TriangleIndices& t = scene.triangles[i];
        const Vec3f& a = scene.vertices[t[0]];
        if (cross(scene.vertices[t[1]] - a, scene.vertices[t[2]] - a) == Vec3f{0.f, 0.f, 0.f})
            if (degenerate++ == 0) first = i;
    }
    if (degenerate)
        scene.warn(path + ": " + std::to_string(degenerate) + " degenerate (zero-area) triangle" +
                   (degenerate == 1 ? "" : "s") + " kept, the first is triangle " +
                   std::to_string(first));
    return scene;
}

Scene load_scene_file(const std::string& path) {
    return detail::lower_extension(path) == "json" ? load_scene_json(path) : load_mesh_file(path);
}

}  // namespace rtt
