// Binary PLY triangle meshes read without assimp: the form scanned meshes usually come in (x, y, z
// and perhaps normals per vertex, one index list per face). Through assimp in its sandbox
// (assimp_sandbox.h) a 900k-triangle scan took 0.55 s to load, mostly the copies and page faults
// of the child's reply (docs/benchmarks.md, "First image"). Every other PLY (ASCII, vertex
// colours, other elements or face properties, points and lines, indices out of range, a file
// shorter or longer than its header says) is left to the assimp path, whose checks and messages
// stay the one account of a malformed file; on the files read here both give the same Scene
// (tests/import_test.cpp, "PlyBinaryReadsAsAssimpDoes").
#include <array>
#include <bit>
#include <charconv>
#include <cstring>
#include <optional>

#include "rtt/memory_budget.h"
#include "scene/importers.h"
#include "scene/text_reader.h"

namespace rtt::detail {
namespace {

enum class Type : uint8_t { none, i8, u8, i16, u16, i32, u32, f32, f64 };

Type type_of(std::string_view t) {
    if (t == "char" || t == "int8") return Type::i8;
    if (t == "uchar" || t == "uint8") return Type::u8;
    if (t == "short" || t == "int16") return Type::i16;
    if (t == "ushort" || t == "uint16") return Type::u16;
    if (t == "int" || t == "int32") return Type::i32;
    if (t == "uint" || t == "uint32") return Type::u32;
    if (t == "float" || t == "float32") return Type::f32;
    if (t == "double" || t == "float64") return Type::f64;
    return Type::none;
}

size_t size_of(Type t) {
    switch (t) {
        case Type::i8:
        case Type::u8:
            return 1;
        case Type::i16:
        case Type::u16:
            return 2;
        case Type::i32:
        case Type::u32:
        case Type::f32:
            return 4;
        case Type::f64:
            return 8;
        case Type::none:
            break;
    }
    return 0;
}

/// The binary records of the file's body, in its byte order.
class Body {
public:
    Body(std::string_view bytes, bool big_endian) : bytes_(bytes), swap_(big_endian) {}

    bool has(size_t n) const { return bytes_.size() - at_ >= n; }
    size_t left() const { return bytes_.size() - at_; }
    void skip(size_t n) { at_ += n; }

    /// A value of type t as assimp converts it: floats and doubles to float (rounded), integers
    /// by value.
    template <typename Out>
    Out read(Type t) {
        switch (t) {
            case Type::i8:
                return Out(int8_t(bits<uint8_t>()));
            case Type::u8:
                return Out(bits<uint8_t>());
            case Type::i16:
                return Out(int16_t(bits<uint16_t>()));
            case Type::u16:
                return Out(bits<uint16_t>());
            case Type::i32:
                return Out(int32_t(bits<uint32_t>()));
            case Type::u32:
                return Out(bits<uint32_t>());
            case Type::f32:
                return Out(std::bit_cast<float>(bits<uint32_t>()));
            case Type::f64:
                return Out(std::bit_cast<double>(bits<uint64_t>()));
            case Type::none:
                break;
        }
        return Out(0);
    }

private:
    template <typename U>
    U bits() {
        U v;
        std::memcpy(&v, bytes_.data() + at_, sizeof v);
        at_ += sizeof v;
        if (!swap_) return v;
        if constexpr (sizeof v == 2) return __builtin_bswap16(v);
        if constexpr (sizeof v == 4) return __builtin_bswap32(v);
        if constexpr (sizeof v == 8) return __builtin_bswap64(v);
        return v;
    }

    std::string_view bytes_;
    size_t at_ = 0;
    bool swap_;
};

struct Property {
    std::string name;
    Type type = Type::none;        ///< Of a scalar, or of a list's items.
    Type count_type = Type::none;  ///< Of a list's count; none for a scalar.
};

struct Element {
    std::string name;
    uint64_t count = 0;
    std::vector<Property> props;
};

/// Vertex properties assimp reads as colours: a file with them keeps the assimp path, which
/// turns them into materials.
bool is_colour(std::string_view name) {
    for (const char* part : {"red", "green", "blue", "alpha"})
        if (name.find(part) != std::string_view::npos) return true;
    return name == "r" || name == "g" || name == "b" || name == "a";
}

}  // namespace

std::optional<Scene> import_ply_binary(const std::string& path) {
    const std::string text = read_text_file(path);
    // Header: "ply", a binary format, then vertex and face elements only.
    std::vector<Element> elements;
    bool big_endian = false, format = false;
    size_t pos = 0;
    Tokens tk;
    for (int line = 1;; ++line) {
        const size_t end = text.find('\n', pos);
        if (end == std::string::npos) return std::nullopt;
        split_tokens(std::string_view(text).substr(pos, end - pos), tk);
        pos = end + 1;
        if (line == 1) {
            if (tk.size() != 1 || tk[0] != "ply") return std::nullopt;
            continue;
        }
        if (tk.empty() || tk[0] == "comment" || tk[0] == "obj_info") continue;
        if (tk[0] == "end_header" && tk.size() == 1) break;
        if (tk[0] == "format" && tk.size() == 3 && !format) {
            if (tk[1] != "binary_little_endian" && tk[1] != "binary_big_endian")
                return std::nullopt;
            big_endian = tk[1] == "binary_big_endian";
            format = true;
        } else if (tk[0] == "element" && tk.size() == 3) {
            uint64_t count = 0;
            const auto [p, ec] = std::from_chars(tk[2].data(), tk[2].data() + tk[2].size(), count);
            if (ec != std::errc() || p != tk[2].data() + tk[2].size()) return std::nullopt;
            elements.push_back({std::string(tk[1]), count, {}});
        } else if (tk[0] == "property" && !elements.empty()) {
            Property prop;
            if (tk.size() == 5 && tk[1] == "list") {
                prop = {std::string(tk[4]), type_of(tk[3]), type_of(tk[2])};
                if (prop.count_type == Type::none) return std::nullopt;
            } else if (tk.size() == 3) {
                prop = {std::string(tk[2]), type_of(tk[1]), Type::none};
            } else {
                return std::nullopt;
            }
            if (prop.type == Type::none) return std::nullopt;
            elements.back().props.push_back(prop);
        } else {
            return std::nullopt;
        }
    }
    if (!format || elements.size() != 2 || elements[0].name != "vertex" ||
        elements[1].name != "face")
        return std::nullopt;
    const Element& vertex = elements[0];
    const Element& face = elements[1];
    if (vertex.count == 0 || face.count == 0 || vertex.count >= invalid_triangle ||
        face.count >= invalid_triangle || face.props.size() != 1 ||
        face.props[0].count_type == Type::none ||
        (face.props[0].name != "vertex_indices" && face.props[0].name != "vertex_index") ||
        face.props[0].type == Type::f32 || face.props[0].type == Type::f64)
        return std::nullopt;
    // What each vertex property is: x, y, z (0-2), nx, ny, nz (3-5) or skipped (-1).
    std::vector<int> slot(vertex.props.size(), -1);
    int seen[6] = {};
    size_t record = 0;
    for (size_t k = 0; k < vertex.props.size(); ++k) {
        const Property& p = vertex.props[k];
        if (p.count_type != Type::none || is_colour(p.name)) return std::nullopt;
        for (int s = 0; s < 6; ++s)
            if (p.name == std::array{"x", "y", "z", "nx", "ny", "nz"}[size_t(s)]) {
                slot[k] = s;
                if (seen[s]++) return std::nullopt;  // named twice
            }
        record += size_of(p.type);
    }
    const bool has_normals = seen[3] || seen[4] || seen[5];
    if (!seen[0] || !seen[1] || !seen[2] || (has_normals && !(seen[3] && seen[4] && seen[5])))
        return std::nullopt;

    Body body(std::string_view(text).substr(pos), big_endian);
    if (body.left() / record < vertex.count) return std::nullopt;
    std::vector<Vec3f> verts(vertex.count), normals(has_normals ? vertex.count : 0);
    for (uint64_t v = 0; v < vertex.count; ++v) {
        float value[6] = {};
        for (size_t k = 0; k < vertex.props.size(); ++k) {
            if (slot[k] < 0)
                body.skip(size_of(vertex.props[k].type));
            else
                value[slot[k]] = body.read<float>(vertex.props[k].type);
        }
        verts[v] = {value[0], value[1], value[2]};
        // A broken normal falls back to the geometric normal (the zero vector), as assimp's.
        if (has_normals) {
            const Vec3f n{value[3], value[4], value[5]};
            normals[v] = is_finite(n) ? n : Vec3f{0.f};
        }
    }
    const Property& list = face.props[0];
    const size_t count_size = size_of(list.count_type), index_size = size_of(list.type);
    // A face takes at least a count and three indices: a header promising more faces than the
    // body holds allocates nothing.
    if (body.left() / (count_size + 3 * index_size) < face.count) return std::nullopt;
    std::vector<TriangleIndices> tris;
    tris.reserve(face.count);
    std::vector<uint32_t> poly;
    for (uint64_t f = 0; f < face.count; ++f) {
        if (!body.has(count_size)) return std::nullopt;
        const int64_t n = body.read<int64_t>(list.count_type);
        if (n < 3 || !body.has(size_t(n) * index_size)) return std::nullopt;
        poly.resize(size_t(n));
        for (uint32_t& i : poly) {
            const int64_t index = body.read<int64_t>(list.type);
            if (index < 0 || uint64_t(index) >= vertex.count) return std::nullopt;
            i = uint32_t(index);
        }
        append_fan(poly.data(), poly.size(), tris);
    }
    if (body.left() != 0) return std::nullopt;
    // As Scene::add_mesh would make it, without copying the arrays.
    require_memory(scene_memory_bytes(verts.size(), tris.size()),
                   "a scene of " + std::to_string(tris.size()) + " triangles");
    Scene scene;
    scene.name = path;
    scene.triangle_material.assign(tris.size(), scene.add_material(Material{}));
    scene.vertices = std::move(verts);
    scene.triangles = std::move(tris);
    scene.normals = std::move(normals);
    return scene;
}

}  // namespace rtt::detail
