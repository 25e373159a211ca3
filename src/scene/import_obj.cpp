// Wavefront OBJ + MTL reader.
//
// OBJ is the interchange format CONVENTIONS is written for ("the index is simply the face's
// position in the file"), and outside checkers load the same file with their own parser. assimp
// 5.2 parses decimals with its fast_atof, which is not correctly rounded: about 5% of the
// coordinates of an OBJ written with "%.9g" come back one ulp off (measured on 90,000 random
// coordinates), so a checker's triangles would differ from ours in the last bit. This reader
// uses std::from_chars (correctly rounded), keeps every face in file order, and reports errors
// with line numbers.
#include <algorithm>
#include <filesystem>
#include <optional>
#include <unordered_map>
#include <unordered_set>

#include "scene/text_reader.h"
#include "scene/texture_colour.h"

namespace rtt::detail {
namespace {

/// One index of an "f" vertex: 1-based, or negative = relative to the `count` defined so far.
/// Returns the 0-based index; the upper bound is checked once the whole file is read.
int64_t obj_index(const TextParser& p, std::string_view t, size_t count) {
    const int64_t v = p.integer(t);
    if (v == 0) p.fail("vertex index 0 (OBJ indices start at 1)");
    if (v < 0 && v < -int64_t(count))  // not -v > count: -INT64_MIN overflows
        p.fail("relative index " + std::to_string(v) + " but only " + std::to_string(count) +
               " defined so far");
    return v > 0 ? v - 1 : int64_t(count) + v;
}

/// The materials of an MTL file by name: Kd, Ks, Ns and illum (0 and 1 mean no highlights), and
/// map_Kd as its mean colour, times Kd when both are given (texture_colour.h); other statements
/// (transparency, bump maps, ...) do not apply to rtt's materials.
std::unordered_map<std::string, Material> read_mtl(const std::string& path, Scene& scene) {
    std::unordered_map<std::string, Material> out;
    std::unordered_map<std::string, bool> no_highlights;
    std::unordered_map<std::string, Vec3f> texture_mean;
    std::unordered_set<std::string> kd_given;
    TextParser p{path};
    std::string cur;
    for_each_line(TextFile(path).text(), false, [&](const Tokens& tk, int line) {
        p.line = line;
        const std::string_view key = tk[0];
        if (key == "newmtl") {
            // An unnamed material is what an unnamed "usemtl" picks (exporters write both).
            if (tk.size() < 2)
                scene.warn(path + ":" + std::to_string(line) +
                           ": newmtl without a name, used by usemtl without one");
            cur = tk.size() < 2 ? std::string() : std::string(tk[1]);
            out[cur] = Material{};
            out[cur].name = cur;
        } else if (key == "map_Kd") {
            if (out.empty()) p.fail("map_Kd before newmtl");
            if (tk.size() < 2) p.fail("expected a file name after 'map_Kd'");
            // Options (-s 1 1 1, -clamp on, ...) come first; the file name is the last token.
            const std::filesystem::path file =
                std::filesystem::path(path).parent_path() / std::string(tk.back());
            if (const std::optional<Vec3f> mean = mean_image_colour(file.string()))
                texture_mean[cur] = *mean;
            else
                scene.warn(path + ":" + std::to_string(line) + ": texture " + file.string() +
                           " cannot be read; material \"" + cur + "\" keeps its Kd");
        } else if (key == "Kd" || key == "Ks" || key == "Ns" || key == "illum") {
            if (out.empty()) p.fail(std::string(key) + " before newmtl");
            if (tk.size() < 2) p.fail("expected a value after '" + std::string(key) + "'");
            if (tk[1] == "spectral" || tk[1] == "xyz") return;  // not RGB: keep the default
            const float r = p.number(tk[1]);
            // "Kd r" alone means grey r (MTL spec). Colours are clamped to [0, 1].
            const Vec3f c = tk.size() >= 4 ? Vec3f{r, p.number(tk[2]), p.number(tk[3])} : Vec3f{r};
            const Vec3f clamped = min(max(c, Vec3f{0.f}), Vec3f{1.f});
            Material& m = out[cur];
            if (key == "Kd") {
                m.diffuse = clamped;
                kd_given.insert(cur);
            } else if (key == "Ks")
                m.specular = clamped;
            else if (key == "Ns")
                m.shininess = std::max(r, 0.f);
            else
                no_highlights[cur] = r < 2.f;
        }
    });
    for (auto& [name, m] : out) {
        if (no_highlights[name]) m.specular = Vec3f{0.f};
        const auto tex = texture_mean.find(name);
        if (tex != texture_mean.end())
            m.diffuse = (kd_given.count(name) ? m.diffuse : Vec3f{1.f}) * tex->second;
    }
    return out;
}

class ObjReader {
public:
    explicit ObjReader(const std::string& path) : path_(path), p_{path} { scene_.name = path; }

    Scene run() {
        const TextFile file(path_);
        const std::string_view text = file.text();
        reserve_for(text);
        for_each_line(text, true, [&](const Tokens& tk, int line) {
            p_.line = line;
            statement(tk);
        });
        p_.line = 0;
        finish();
        return std::move(scene_);
    }

private:
    static constexpr int64_t no_normal = -1;
    struct Corner {
        int64_t v, n;
    };

    /// Room for the vertices, normals and triangles the lines starting with "v ", "vn" and "f"
    /// promise (a face of three corners each): grown by doubling instead, the arrays' copies and
    /// fresh pages were half of reading a 900k-triangle OBJ (docs/benchmarks.md, "First image").
    void reserve_for(std::string_view text) {
        size_t v = 0, vn = 0, f = 0;
        for (size_t pos = 0; pos + 1 < text.size();) {
            const char a = text[pos], b = text[pos + 1];
            v += a == 'v' && (b == ' ' || b == '\t');
            vn += a == 'v' && b == 'n';
            f += a == 'f' && (b == ' ' || b == '\t');
            const size_t end = text.find('\n', pos);
            if (end == std::string_view::npos) break;
            pos = end + 1;
        }
        positions_.reserve(v);
        normals_.reserve(vn);
        tri_corners_.reserve(3 * f);
        tri_material_.reserve(f);
        tri_line_.reserve(f);
    }

    void statement(const Tokens& tk) {
        const std::string_view key = tk[0];
        if (key == "v") {
            positions_.push_back(p_.point(tk, 1, "vertex", true));
        } else if (key == "vn") {
            if (tk.size() < 4) p_.fail("expected 3 numbers for a normal");
            normals_.push_back({p_.number(tk[1]), p_.number(tk[2]), p_.number(tk[3])});
        } else if (key == "f") {
            face(tk);
        } else if (key == "l" || key == "p") {
            ++skipped_[key == "p" ? 0 : 1];
        } else if (key == "usemtl") {
            material_ = tk.size() < 2 ? std::string() : std::string(tk[1]);
            material_line_ = p_.line;
        } else if (key == "mtllib") {
            for (size_t i = 1; i < tk.size(); ++i) load_mtl(std::string(tk[i]));
        }
        // Everything else (vt, o, g, s, free-form geometry, vendor extensions) does not change
        // the triangles or their order.
    }

    void face(const Tokens& tk) {
        const size_t n = tk.size() - 1;
        if (n < 3) {
            ++skipped_[n <= 1 ? 0 : 1];
            scene_.warn(path_ + ":" + std::to_string(p_.line) + ": face with " + std::to_string(n) +
                        (n == 1 ? " vertex" : " vertices") + " skipped");
            return;
        }
        corners_.clear();
        for (size_t i = 1; i < tk.size(); ++i) {
            // v, v/t, v/t/n or v//n
            const std::string_view t = tk[i];
            const size_t s1 = t.find('/');
            Corner c{obj_index(p_, t.substr(0, s1), positions_.size()), no_normal};
            if (s1 != std::string_view::npos) {
                const size_t s2 = t.find('/', s1 + 1);
                if (s2 != std::string_view::npos && s2 + 1 < t.size())
                    c.n = obj_index(p_, t.substr(s2 + 1), normals_.size());
            }
            has_normals_ = has_normals_ || c.n != no_normal;
            corners_.push_back(c);
        }
        const uint32_t mat = material_index();
        const size_t first = tri_corners_.size() / 3;
        // The fan (v0 v1 v2), (v0 v2 v3), ... of CONVENTIONS.
        for (size_t k = 1; k + 1 < n; ++k)
            for (size_t c : {size_t(0), k, k + 1}) tri_corners_.push_back(corners_[c]);
        tri_material_.resize(first + (n - 2), mat);
        tri_line_.resize(first + (n - 2), p_.line);
    }

    void load_mtl(const std::string& name) {
        const std::filesystem::path file = std::filesystem::path(path_).parent_path() / name;
        std::error_code ec;
        // A missing MTL file is common (not shipped with the OBJ): its faces get the default.
        if (!std::filesystem::is_regular_file(file, ec)) {
            scene_.warn(path_ + ":" + std::to_string(p_.line) + ": material library " + name +
                        " not found; its materials are grey");
            return;
        }
        // Each file is read once: repeating "mtllib big.mtl" must not cost a read per line.
        if (!loaded_mtl_.insert(file.string()).second) return;
        for (auto& [key, m] : read_mtl(file.string(), scene_)) mtl_.insert_or_assign(key, m);
    }

    /// The scene material of the current "usemtl" name, numbered by first use. Its values are
    /// looked up in finish(): like assimp, an "mtllib" may come after the faces using it.
    uint32_t material_index() {
        const auto next = uint32_t(material_names_.size());
        const auto [it, added] = material_ids_.try_emplace(material_, next);
        if (added) {
            material_names_.push_back(material_);
            material_lines_.push_back(material_line_);
        }
        return it->second;
    }

    /// Checks every index against the final counts (positive indices may point forward, as
    /// assimp allows) and builds the mesh: positions as read, or one vertex per distinct
    /// (position, normal) pair when the file has normals.
    void finish() {
        if (tri_corners_.empty())
            throw Error(path_, 0,
                        "no triangles (skipped " + std::to_string(skipped_[0]) + " points and " +
                            std::to_string(skipped_[1]) + " lines)");
        if (positions_.size() >= invalid_triangle || tri_corners_.size() / 3 >= invalid_triangle)
            throw Error(path_, 0, "more than 2^32 - 2 vertices or triangles");
        for (size_t i = 0; i < tri_corners_.size(); ++i) {
            const Corner& c = tri_corners_[i];
            if (c.v >= int64_t(positions_.size()))
                throw Error(path_, tri_line_[i / 3],
                            "face uses vertex " + std::to_string(c.v + 1) + " but the file has " +
                                std::to_string(positions_.size()));
            if (c.n >= int64_t(normals_.size()))
                throw Error(path_, tri_line_[i / 3],
                            "face uses normal " + std::to_string(c.n + 1) + " but the file has " +
                                std::to_string(normals_.size()));
        }
        std::vector<TriangleIndices> tris(tri_corners_.size() / 3);
        std::vector<Vec3f> verts, norms;
        if (!has_normals_) {
            verts = std::move(positions_);
            for (size_t i = 0; i < tri_corners_.size(); ++i)
                tris[i / 3][i % 3] = uint32_t(tri_corners_[i].v);
        } else {
            std::unordered_map<uint64_t, uint32_t> ids;
            for (size_t i = 0; i < tri_corners_.size(); ++i) {
                const Corner& c = tri_corners_[i];
                const uint64_t key = uint64_t(c.v) << 32 | uint32_t(c.n + 1);
                auto [it, added] = ids.try_emplace(key, uint32_t(verts.size()));
                if (added) {
                    verts.push_back(positions_[c.v]);
                    const Vec3f n = c.n != no_normal ? normals_[c.n] : Vec3f{0.f};
                    norms.push_back(is_finite(n) ? n : Vec3f{0.f});
                }
                tris[i / 3][i % 3] = it->second;
            }
        }
        scene_.vertices = std::move(verts);
        scene_.normals = std::move(norms);
        scene_.triangles = std::move(tris);
        scene_.triangle_material = std::move(tri_material_);
        for (size_t i = 0; i < material_names_.size(); ++i) {
            const std::string& name = material_names_[i];
            const auto m = mtl_.find(name);
            if (m == mtl_.end() && !name.empty())
                scene_.warn(path_ + ":" + std::to_string(material_lines_[i]) + ": material '" +
                            name + "' is in no material library; grey instead");
            scene_.add_material(m == mtl_.end() ? Material{} : m->second);
        }
    }

    const std::string& path_;
    TextParser p_;
    Scene scene_;
    std::vector<Vec3f> positions_, normals_;
    std::vector<Corner> corners_;
    large_vector<Corner> tri_corners_;  ///< Three per triangle: tens of MB for a scan.
    std::vector<uint32_t> tri_material_;
    std::vector<int> tri_line_;
    std::vector<int> material_lines_;  ///< The usemtl line of each material's first use.
    int material_line_ = 0;
    std::string material_;
    std::unordered_map<std::string, Material> mtl_;
    std::unordered_map<std::string, uint32_t> material_ids_;
    std::vector<std::string> material_names_;
    std::unordered_set<std::string> loaded_mtl_;
    bool has_normals_ = false;
    size_t skipped_[2] = {0, 0};  // points, lines
};

}  // namespace

Scene import_obj(const std::string& path) {
    return ObjReader(path).run();
}

}  // namespace rtt::detail
