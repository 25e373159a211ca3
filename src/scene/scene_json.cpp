// rtt's JSON scene files (schema and example: docs/scene-format.md).
//
// Strict by design: unknown and duplicate keys are errors (they are almost always typos), every
// number must be finite and in range, and each error names the file and the JSON pointer of the
// offending value ("scene.json: /lights/2/position: expected 3 numbers"); syntax errors name the
// line instead.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <unordered_map>

#include "rtt/error.h"
#include "rtt/scene_io.h"
#include "scene/affine.h"
#include "scene/importers.h"

namespace rtt {
namespace {

using detail::Affine;
using nlohmann::json;

/// Parses `text`; a syntax error becomes "path:line: message" (nlohmann reports a byte offset,
/// which we turn into a line), a repeated key in one object "path: duplicate key".
json parse_json(const std::string& path, const std::string& text) {
    std::vector<std::set<std::string>> keys;  // keys seen so far in each open object
    const json::parser_callback_t on_event = [&](int, json::parse_event_t event, json& parsed) {
        if (event == json::parse_event_t::object_start)
            keys.emplace_back();
        else if (event == json::parse_event_t::object_end)
            keys.pop_back();
        else if (event == json::parse_event_t::key &&
                 !keys.back().insert(parsed.get<std::string>()).second)
            throw Error(path, 0,
                        "duplicate key \"" + detail::one_line(parsed.get<std::string>()) + "\"");
        return true;
    };
    try {
        return json::parse(text, on_event);
    } catch (const json::parse_error& e) {
        // e.byte is the 1-based offset of the last character read.
        const size_t end = std::min<size_t>(e.byte > 0 ? e.byte - 1 : 0, text.size());
        const int line = 1 + int(std::count(text.begin(), text.begin() + ptrdiff_t(end), '\n'));
        // what() = "[json.exception.parse_error.101] parse error at line L, column C: detail"
        std::string what = e.what();
        if (const size_t at = what.find("column "); at != std::string::npos)
            if (const size_t colon = what.find(": ", at); colon != std::string::npos)
                what = what.substr(colon + 2);
        throw Error(path, line, "JSON syntax error: " + detail::one_line(what));
    } catch (const json::exception& e) {  // e.g. a number too large for a double
        std::string what = e.what();      // "[json.exception.out_of_range.406] number overflow ..."
        if (const size_t at = what.find("] "); at != std::string::npos) what = what.substr(at + 2);
        throw Error(path, 0, "JSON error: " + detail::one_line(what));
    }
}

class JsonScene {
public:
    explicit JsonScene(const std::string& path) : path_(path) { scene_.name = path; }

    Scene run(const json& root) {
        check_keys(root, "", {"meshes", "materials", "lights", "camera", "background"});
        if (const json* m = field(root, "materials")) {
            for_each(*m, "/materials", [&](const json& j, const std::string& ptr) {
                Material mat = material(j, ptr, true);
                if (named_.count(mat.name))
                    fail(ptr + "/name", "material \"" + mat.name + "\" defined twice");
                named_[mat.name] = scene_.add_material(mat);
            });
        }
        const json* meshes = field(root, "meshes");
        if (!meshes) fail("", "missing key \"meshes\"");
        for_each(*meshes, "/meshes", [&](const json& j, const std::string& ptr) { mesh(j, ptr); });
        if (meshes->empty()) fail("/meshes", "no meshes");
        if (const json* l = field(root, "lights")) {
            if (l->is_array() && l->size() > max_lights)
                fail("/lights", std::to_string(l->size()) + " lights; at most " +
                                    std::to_string(max_lights) + " are supported");
            for_each(*l, "/lights", [&](const json& j, const std::string& ptr) {
                scene_.lights.push_back(light(j, ptr));
            });
        }
        if (const json* c = field(root, "camera")) scene_.camera = camera(*c, "/camera");
        if (const json* b = field(root, "background"))
            scene_.background = color(*b, "/background", false);
        validate(scene_);
        return std::move(scene_);
    }

private:
    [[noreturn]] void fail(const std::string& ptr, const std::string& message) const {
        throw Error(path_, 0, (ptr.empty() ? "/" : ptr) + ": " + message);
    }

    static const json* field(const json& obj, const char* key) {
        const auto it = obj.find(key);
        return it == obj.end() ? nullptr : &*it;
    }

    void check_keys(const json& j, const std::string& ptr,
                    std::initializer_list<const char*> allowed) const {
        if (!j.is_object()) fail(ptr, "expected an object");
        for (const auto& item : j.items()) {
            // Not a structured binding: clang before 16 cannot capture one in the lambda.
            const std::string& key = item.key();
            if (std::any_of(allowed.begin(), allowed.end(),
                            [&](const char* a) { return key == a; }))
                continue;
            std::string list;
            for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
            fail(ptr,
                 "unknown key \"" + detail::one_line(key) + "\" (expected one of: " + list + ")");
        }
    }

    template <typename Fn>
    void for_each(const json& j, const std::string& ptr, Fn&& fn) const {
        if (!j.is_array()) fail(ptr, "expected an array");
        for (size_t i = 0; i < j.size(); ++i) fn(j[i], ptr + "/" + std::to_string(i));
    }

    float number(const json& j, const std::string& ptr,
                 double lo = std::numeric_limits<float>::lowest(),
                 double hi = std::numeric_limits<float>::max()) const {
        if (!j.is_number()) fail(ptr, "expected a number");
        const double v = j.get<double>();
        if (!(std::fabs(v) <= std::numeric_limits<float>::max()))
            fail(ptr, "number out of float range");
        if (v < lo || v > hi) {
            const auto bound = [](double b) {
                return std::fabs(b) == std::numeric_limits<float>::max()
                           ? std::string(b < 0 ? "-inf" : "inf")
                           : json(b).dump();
            };
            fail(ptr, "value " + j.dump() + " outside [" + bound(lo) + ", " + bound(hi) + "]");
        }
        return float(v);
    }

    Vec3f vec3(const json& j, const std::string& ptr,
               double lo = std::numeric_limits<float>::lowest()) const {
        if (!j.is_array() || j.size() != 3 ||
            !std::all_of(j.begin(), j.end(), [](const json& x) { return x.is_number(); }))
            fail(ptr, "expected 3 numbers");
        return {number(j[0], ptr + "/0", lo), number(j[1], ptr + "/1", lo),
                number(j[2], ptr + "/2", lo)};
    }

    /// RGB in [0, 1], or any non-negative values when `bounded` is false (light colours).
    Vec3f color(const json& j, const std::string& ptr, bool bounded) const {
        const Vec3f c = vec3(j, ptr, 0.0);
        if (bounded && std::max({c.x, c.y, c.z}) > 1.f)
            fail(ptr, "colour components must be in [0, 1]");
        return c;
    }

    std::string string(const json& j, const std::string& ptr) const {
        if (!j.is_string()) fail(ptr, "expected a string");
        return j.get<std::string>();
    }

    Material material(const json& j, const std::string& ptr, bool name_required) const {
        check_keys(j, ptr, {"name", "diffuse", "specular", "shininess", "mirror"});
        Material m;
        if (const json* v = field(j, "name"))
            m.name = string(*v, ptr + "/name");
        else if (name_required)
            fail(ptr, "missing key \"name\"");
        if (const json* v = field(j, "diffuse")) m.diffuse = color(*v, ptr + "/diffuse", true);
        if (const json* v = field(j, "specular")) m.specular = color(*v, ptr + "/specular", true);
        if (const json* v = field(j, "shininess"))
            m.shininess = number(*v, ptr + "/shininess", 0.0);
        if (const json* v = field(j, "mirror")) m.mirror = number(*v, ptr + "/mirror", 0.0, 1.0);
        return m;
    }

    Light light(const json& j, const std::string& ptr) const {
        Light l;
        const json* type = j.is_object() ? field(j, "type") : nullptr;
        const std::string kind = type ? string(*type, ptr + "/type") : "omni";
        if (kind == "omni") {
            check_keys(j, ptr, {"type", "position", "color", "intensity"});
        } else if (kind == "spot") {
            check_keys(j, ptr,
                       {"type", "position", "direction", "inner_angle", "outer_angle", "color",
                        "intensity"});
            l.kind = LightKind::spot;
        } else {
            fail(ptr + "/type",
                 "unknown light type \"" + detail::one_line(kind) + "\" (expected omni or spot)");
        }
        const json* pos = field(j, "position");
        if (!pos) fail(ptr, "missing key \"position\"");
        l.position = vec3(*pos, ptr + "/position");
        if (const json* v = field(j, "color")) l.color = color(*v, ptr + "/color", false);
        if (const json* v = field(j, "intensity"))
            l.intensity = number(*v, ptr + "/intensity", 0.0);
        if (const json* v = field(j, "direction")) l.direction = vec3(*v, ptr + "/direction");
        if (const json* v = field(j, "inner_angle"))
            l.inner_angle_deg = number(*v, ptr + "/inner_angle", 0.0, 180.0);
        if (const json* v = field(j, "outer_angle"))
            l.outer_angle_deg = number(*v, ptr + "/outer_angle", 0.0, 180.0);
        if (l.kind == LightKind::spot && length(l.direction) == 0.f)
            fail(ptr + "/direction", "zero vector");
        if (l.inner_angle_deg > l.outer_angle_deg)
            fail(ptr, "inner_angle is larger than outer_angle");
        return l;
    }

    Camera camera(const json& j, const std::string& ptr) const {
        check_keys(j, ptr, {"position", "target", "up", "fovy"});
        Camera c;
        const json* pos = field(j, "position");
        const json* target = field(j, "target");
        if (!pos || !target) fail(ptr, "\"position\" and \"target\" are required");
        c.position = vec3(*pos, ptr + "/position");
        c.target = vec3(*target, ptr + "/target");
        if (const json* v = field(j, "up")) c.up = vec3(*v, ptr + "/up");
        if (const json* v = field(j, "fovy")) c.fovy_deg = number(*v, ptr + "/fovy", 0.0, 180.0);
        if (!(c.fovy_deg > 0.f && c.fovy_deg < 180.f))
            fail(ptr + "/fovy", "must be strictly between 0 and 180");
        if (c.target == c.position) fail(ptr + "/target", "equals the position");
        if (length(cross(c.target - c.position, c.up)) == 0.f)
            fail(ptr + "/up", "parallel to the view direction");
        return c;
    }

    /// {"matrix": [16 numbers, row-major]} or {"translate", "rotate" (degrees), "scale"}:
    /// p' = T Rz Ry Rx S p.
    Affine transform(const json& j, const std::string& ptr) const {
        check_keys(j, ptr, {"matrix", "translate", "rotate", "scale"});
        Affine a;
        if (const json* m = field(j, "matrix")) {
            if (j.size() != 1)
                fail(ptr, "\"matrix\" cannot be combined with translate/rotate/scale");
            if (!m->is_array() || m->size() != 16)
                fail(ptr + "/matrix", "expected 16 numbers (row-major 4x4)");
            for (int i = 0; i < 16; ++i) {
                const float v = number((*m)[i], ptr + "/matrix/" + std::to_string(i));
                if (i < 12)
                    a.m[i / 4][i % 4] = v;
                else if (v != (i == 15 ? 1.f : 0.f))
                    fail(ptr + "/matrix", "the last row must be 0 0 0 1");
            }
        } else {
            if (const json* v = field(j, "scale")) {
                const Vec3f s =
                    v->is_number() ? Vec3f{number(*v, ptr + "/scale")} : vec3(*v, ptr + "/scale");
                a = detail::scaling(s.x, s.y, s.z);
            }
            if (const json* v = field(j, "rotate")) {
                const Vec3f r = vec3(*v, ptr + "/rotate");
                a = detail::rotation(2, r.z) * detail::rotation(1, r.y) * detail::rotation(0, r.x) *
                    a;
            }
            if (const json* v = field(j, "translate")) {
                const Vec3f t = vec3(*v, ptr + "/translate");
                a = detail::translation(t.x, t.y, t.z) * a;
            }
        }
        if (a.determinant() == 0.0) fail(ptr, "singular transform (a zero scale?)");
        return a;
    }

    uint32_t default_material() {
        if (default_material_ == invalid_triangle) default_material_ = scene_.add_material({});
        return default_material_;
    }

    void mesh(const json& j, const std::string& ptr) {
        check_keys(j, ptr, {"path", "vertices", "triangles", "normals", "transform", "material"});
        const json* path = field(j, "path");
        if (!path == !field(j, "vertices"))
            fail(ptr, "needs either \"path\" or \"vertices\" + \"triangles\"");
        const json* t = field(j, "transform");
        const Affine xf = t ? transform(*t, ptr + "/transform") : Affine{};
        std::optional<uint32_t> mat;
        if (const json* m = field(j, "material")) {
            if (m->is_string()) {
                const auto it = named_.find(m->get<std::string>());
                if (it == named_.end())
                    fail(ptr + "/material",
                         "no material named \"" + detail::one_line(m->get<std::string>()) + "\"");
                mat = it->second;
            } else {
                mat = scene_.add_material(material(*m, ptr + "/material", false));
            }
        }
        Scene part = path ? file_mesh(*path, j, ptr) : inline_mesh(j, ptr);
        if (!mat && !path) mat = default_material();
        append(part, xf, mat, ptr);
    }

    Scene file_mesh(const json& path, const json& j, const std::string& ptr) const {
        if (field(j, "triangles") || field(j, "normals"))
            fail(ptr, "\"path\" cannot be combined with inline geometry");
        std::filesystem::path file = string(path, ptr + "/path");
        if (file.is_relative()) file = std::filesystem::path(path_).parent_path() / file;
        if (detail::lower_extension(file.string()) == "json")
            fail(ptr + "/path", "a mesh cannot be another JSON scene");
        try {
            return load_mesh_file(file.string());
        } catch (const Error& e) {
            fail(ptr + "/path", e.what());
        }
    }

    Scene inline_mesh(const json& j, const std::string& ptr) const {
        Scene part;
        for_each(j["vertices"], ptr + "/vertices",
                 [&](const json& v, const std::string& p) { part.vertices.push_back(vec3(v, p)); });
        const json* tris = field(j, "triangles");
        if (!tris) fail(ptr, "missing key \"triangles\"");
        for_each(*tris, ptr + "/triangles", [&](const json& t, const std::string& p) {
            if (!t.is_array() || t.size() != 3) fail(p, "expected 3 vertex indices");
            TriangleIndices tri{};
            for (size_t k = 0; k < 3; ++k) {
                if (!t[k].is_number_unsigned())
                    fail(p + "/" + std::to_string(k), "expected a vertex index (integer >= 0)");
                const uint64_t v = t[k].get<uint64_t>();
                if (v >= part.vertices.size())
                    fail(p + "/" + std::to_string(k),
                         "vertex " + std::to_string(v) + " out of range (" +
                             std::to_string(part.vertices.size()) + " vertices)");
                tri[k] = uint32_t(v);
            }
            part.triangles.push_back(tri);
        });
        if (part.triangles.empty()) fail(ptr + "/triangles", "no triangles");
        if (const json* n = field(j, "normals")) {
            for_each(*n, ptr + "/normals", [&](const json& v, const std::string& p) {
                part.normals.push_back(vec3(v, p));
            });
            if (part.normals.size() != part.vertices.size())
                fail(ptr + "/normals", "expected one normal per vertex");
        }
        part.triangle_material.assign(part.triangles.size(), 0);
        return part;
    }

    /// Appends `part` transformed by `xf`; all its triangles get `mat` when given, otherwise
    /// its own materials (a mesh file's), appended to the scene's.
    void append(const Scene& part, const Affine& xf, std::optional<uint32_t> mat,
                const std::string& ptr) {
        // Untransformed parts go in as they are, without a copy before add_mesh's own (tens of
        // MB for a scan).
        const bool identity = xf.is_identity();
        std::vector<Vec3f> moved, moved_normals;
        if (!identity) {
            moved = part.vertices;
            moved_normals = part.normals;
            for (Vec3f& v : moved) {
                v = xf.point(v);
                if (!is_finite(v)) fail(ptr + "/transform", "moves a vertex to infinity");
            }
            for (Vec3f& n : moved_normals) n = xf.normal(n);
        }
        const size_t first = scene_.triangles.size();
        scene_.add_mesh(identity ? part.vertices : moved, part.triangles, mat.value_or(0),
                        identity ? part.normals : moved_normals);
        if (!mat) {
            const auto base = uint32_t(scene_.materials.size());
            scene_.materials.insert(scene_.materials.end(), part.materials.begin(),
                                    part.materials.end());
            for (size_t i = 0; i < part.triangles.size(); ++i)
                scene_.triangle_material[first + i] = base + part.triangle_material[i];
        }
    }

    const std::string& path_;
    Scene scene_;
    std::unordered_map<std::string, uint32_t> named_;
    uint32_t default_material_ = invalid_triangle;
};

}  // namespace

Scene load_scene_json(const std::string& path) {
    detail::require_readable_file(path);
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return JsonScene(path).run(parse_json(path, text.str()));
}

}  // namespace rtt
