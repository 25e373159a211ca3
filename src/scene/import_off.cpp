// Object File Format reader (ASCII OFF and its COFF / NOFF / CNOFF variants).
//
// One vertex per line (x y z, then normal / colour values we ignore), then one face per line
// (n i0 ... i{n-1}, then an optional colour); '#' starts a comment. Faces keep file order and
// are fan-split (CONVENTIONS); faces with fewer than 3 vertices are skipped.
#include <algorithm>

#include "scene/text_reader.h"

namespace rtt::detail {

Scene import_off(const std::string& path) {
    const TextFile file(path);
    const std::string_view text = file.text();
    TextParser p{path};
    Scene scene;
    scene.name = path;
    enum class Stage { header, counts, vertices, faces, done } stage = Stage::header;
    int64_t nv = 0, nf = 0, faces_read = 0;
    size_t skipped = 0;
    std::vector<uint32_t> poly;
    for_each_line(text, false, [&](const Tokens& tk, int line) {
        p.line = line;
        size_t first = 0;  // first token of this line still to read
        if (stage == Stage::header) {
            const std::string_view h = tk[0];
            if (h != "OFF" && h != "COFF" && h != "NOFF" && h != "CNOFF" && h != "NCOFF")
                p.fail(h.size() >= 3 && h.substr(h.size() - 3) == "OFF"
                           ? "unsupported OFF variant '" + one_line(std::string(h)) + "'"
                           : "not an OFF file (the first word must be OFF)");
            stage = Stage::counts;
            if (tk.size() == 1) return;
            first = 1;  // "OFF nv nf ne" on one line
        }
        if (stage == Stage::counts) {
            if (tk.size() - first < 2) p.fail("expected vertex and face counts");
            nv = p.integer(tk[first]);
            nf = p.integer(tk[first + 1]);
            if (nv < 0 || nf < 0 || nv >= int64_t(invalid_triangle))
                p.fail("vertex or face count out of range");
            // Every vertex line takes at least 6 bytes: never reserve more than the file can hold.
            scene.vertices.reserve(std::min(size_t(nv), text.size() / 6));
            stage = nv > 0 ? Stage::vertices : nf > 0 ? Stage::faces : Stage::done;
            return;
        }
        if (stage == Stage::vertices) {
            scene.vertices.push_back(p.point(tk, 0, "vertex", true));
            if (int64_t(scene.vertices.size()) == nv) stage = nf > 0 ? Stage::faces : Stage::done;
            return;
        }
        if (stage == Stage::faces) {
            const int64_t n = p.integer(tk[0]);
            if (n < 0 || n > int64_t(tk.size()) - 1)
                p.fail("face has " + std::to_string(int64_t(tk.size()) - 1) +
                       " values after its vertex count " + std::to_string(n));
            poly.clear();
            for (int64_t k = 1; k <= n; ++k) {
                const int64_t v = p.integer(tk[size_t(k)]);
                if (v < 0 || v >= nv)
                    p.fail("face uses vertex " + std::to_string(v) + " but the file has " +
                           std::to_string(nv) + " (OFF indices start at 0)");
                poly.push_back(uint32_t(v));
            }
            if (n < 3)
                ++skipped;
            else
                append_fan(poly.data(), poly.size(), scene.triangles);
            if (++faces_read == nf) stage = Stage::done;
        }
        // Stage::done: trailing lines (edges, vendor data) are ignored.
    });
    p.line = 0;
    if (stage == Stage::header || stage == Stage::counts) p.fail("missing OFF header or counts");
    if (stage == Stage::vertices)
        p.fail("truncated: " + std::to_string(scene.vertices.size()) + " of " + std::to_string(nv) +
               " vertices");
    if (stage == Stage::faces)
        p.fail("truncated: " + std::to_string(faces_read) + " of " + std::to_string(nf) + " faces");
    if (scene.triangles.empty())
        p.fail("no triangles (skipped " + std::to_string(skipped) +
               " faces with fewer than 3 vertices)");
    scene.triangle_material.assign(scene.triangles.size(), scene.add_material({}));
    return scene;
}

}  // namespace rtt::detail
