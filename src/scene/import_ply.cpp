// PLY triangle meshes read without assimp: the form scanned meshes come in (x, y, z and perhaps
// normals per vertex, one index list per face; binary, or ASCII as the Stanford scans). Through
// assimp in its sandbox (assimp_sandbox.h) a 900k-triangle binary scan took 0.55 s to load,
// mostly the copies and page faults of the child's reply (docs/benchmarks.md, "First image").
// Every other PLY (vertex colours, other elements or face properties, points and lines, indices
// out of range, a file shorter or longer than its header says, ASCII records that are not one
// per line) is left to the assimp path, whose checks and messages stay the one account of a
// malformed file. On the files read here both give the same Scene, except that ASCII numbers are
// rounded correctly (std::from_chars, as in our OBJ reader) where assimp's fast_atof may be one
// ulp off (tests/import_test.cpp, "PlyReadsAsAssimpDoes").
#include <array>
#include <bit>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <optional>

#include "rtt/memory_budget.h"
#include "scene/importers.h"
#include "scene/ply_types.h"
#include "scene/text_reader.h"

namespace rtt::detail {
namespace {

using Type = PlyType;

/// Values in the file's byte order. A value is read as assimp converts it: floats and doubles to
/// float (rounded), integers by value. Every read checks that the bytes are there.
class BinaryBody {
public:
    BinaryBody(std::string_view bytes, bool big_endian) : bytes_(bytes), swap_(big_endian) {}

    /// Values of a record that fit in the rest of the body at most (for allocation guards).
    size_t room(size_t record_bytes) const { return (bytes_.size() - at_) / record_bytes; }
    static size_t least_bytes(Type t) { return ply_size(t); }
    bool skip(Type t) {
        if (bytes_.size() - at_ < ply_size(t)) return false;
        at_ += ply_size(t);
        return true;
    }
    template <typename Out>
    bool read(Type t, Out& out) {
        if (bytes_.size() - at_ < ply_size(t)) return false;
        switch (t) {
            case Type::i8:
                out = Out(int8_t(bits<uint8_t>()));
                break;
            case Type::u8:
                out = Out(bits<uint8_t>());
                break;
            case Type::i16:
                out = Out(int16_t(bits<uint16_t>()));
                break;
            case Type::u16:
                out = Out(bits<uint16_t>());
                break;
            case Type::i32:
                out = Out(int32_t(bits<uint32_t>()));
                break;
            case Type::u32:
                out = Out(bits<uint32_t>());
                break;
            case Type::f32:
                out = Out(std::bit_cast<float>(bits<uint32_t>()));
                break;
            case Type::f64:
                out = Out(std::bit_cast<double>(bits<uint64_t>()));
                break;
            case Type::none:
                return false;
        }
        return true;
    }
    static bool end_record() { return true; }
    bool at_end() const { return at_ == bytes_.size(); }

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

/// Values as text, one record per line: floats parsed correctly rounded (a double property as
/// a double, then rounded to float, as a binary file's double is), integers exactly.
class TextBody {
public:
    explicit TextBody(std::string_view text) : text_(text) {}

    size_t room(size_t record_bytes) const { return (text_.size() - at_) / record_bytes; }
    static size_t least_bytes(Type) { return 2; }  // a digit and a separator
    bool skip(Type) { return !token().empty(); }
    template <typename Out>
    bool read(Type t, Out& out) {
        const std::string_view tk = token();
        const char* end = tk.data() + tk.size();
        std::from_chars_result r{};
        if (t == Type::f32) {
            float v = 0.f;
            r = std::from_chars(tk.data(), end, v);
            out = Out(v);
        } else if (t == Type::f64) {
            double v = 0.0;
            r = std::from_chars(tk.data(), end, v);
            out = Out(v);
        } else {
            int64_t v = 0;
            r = std::from_chars(tk.data(), end, v);
            const auto [lo, hi] = range(t);
            if (v < lo || v > hi) return false;
            out = Out(v);
        }
        return !tk.empty() && r.ec == std::errc() && r.ptr == end;
    }
    /// The rest of the record's line is blank.
    bool end_record() {
        while (at_ < text_.size() && is_space(text_[at_])) ++at_;
        if (at_ == text_.size()) return true;
        if (text_[at_] != '\n') return false;
        ++at_;
        return true;
    }
    bool at_end() {
        while (at_ < text_.size() && (is_space(text_[at_]) || text_[at_] == '\n')) ++at_;
        return at_ == text_.size();
    }

private:
    /// The next value on this line (empty at a line's end).
    std::string_view token() {
        while (at_ < text_.size() && is_space(text_[at_])) ++at_;
        const size_t from = at_;
        while (at_ < text_.size() && !is_space(text_[at_]) && text_[at_] != '\n') ++at_;
        return text_.substr(from, at_ - from);
    }

    /// Blanks within a line.
    static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r'; }

    static std::pair<int64_t, int64_t> range(Type t) {
        switch (t) {
            case Type::i8:
                return {INT8_MIN, INT8_MAX};
            case Type::u8:
                return {0, UINT8_MAX};
            case Type::i16:
                return {INT16_MIN, INT16_MAX};
            case Type::u16:
                return {0, UINT16_MAX};
            case Type::i32:
                return {INT32_MIN, INT32_MAX};
            default:
                return {0, UINT32_MAX};
        }
    }

    std::string_view text_;
    size_t at_ = 0;
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

/// A file this reader takes: its vertex and face elements, what each vertex property is (x, y,
/// z as 0-2, nx, ny, nz as 3-5, skipped as -1), and where its body starts.
struct Layout {
    enum class Format { ascii, little_endian, big_endian } format = Format::ascii;
    Element vertex, face;
    std::vector<int> slot;
    bool normals = false;
    size_t body = 0;
};

/// Vertex properties assimp reads as colours: a file with them keeps the assimp path, which
/// turns them into materials.
bool is_colour(std::string_view name) {
    for (const char* part : {"red", "green", "blue", "alpha"})
        if (name.find(part) != std::string_view::npos) return true;
    return name == "r" || name == "g" || name == "b" || name == "a";
}

/// The header of `text` when it declares a mesh this reader takes, else nullopt.
std::optional<Layout> layout_of(std::string_view text) {
    Layout out;
    std::vector<Element> elements;
    bool format = false;
    Tokens tk;
    for (int line = 1;; ++line) {
        const size_t end = text.find('\n', out.body);
        if (end == std::string::npos) return std::nullopt;
        split_tokens(text.substr(out.body, end - out.body), tk);
        out.body = end + 1;
        if (line == 1) {
            if (tk.size() != 1 || tk[0] != "ply") return std::nullopt;
            continue;
        }
        if (tk.empty() || tk[0] == "comment" || tk[0] == "obj_info") continue;
        if (tk[0] == "end_header" && tk.size() == 1) break;
        if (tk[0] == "format" && tk.size() == 3 && !format) {
            using F = Layout::Format;
            if (tk[1] == "ascii")
                out.format = F::ascii;
            else if (tk[1] == "binary_little_endian")
                out.format = F::little_endian;
            else if (tk[1] == "binary_big_endian")
                out.format = F::big_endian;
            else
                return std::nullopt;
            format = true;
        } else if (tk[0] == "element" && tk.size() == 3) {
            uint64_t count = 0;
            const auto [p, ec] = std::from_chars(tk[2].data(), tk[2].data() + tk[2].size(), count);
            if (ec != std::errc() || p != tk[2].data() + tk[2].size()) return std::nullopt;
            elements.push_back({std::string(tk[1]), count, {}});
        } else if (tk[0] == "property" && !elements.empty()) {
            Property prop;
            if (tk.size() == 5 && tk[1] == "list") {
                prop = {std::string(tk[4]), ply_type(tk[3]), ply_type(tk[2])};
                if (prop.count_type == Type::none) return std::nullopt;
            } else if (tk.size() == 3) {
                prop = {std::string(tk[2]), ply_type(tk[1]), Type::none};
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
    out.vertex = elements[0];
    out.face = elements[1];
    const std::vector<Property>& fp = out.face.props;
    if (out.vertex.count == 0 || out.face.count == 0 || out.vertex.count >= invalid_triangle ||
        out.face.count >= invalid_triangle || fp.size() != 1 || fp[0].count_type == Type::none ||
        ply_float(fp[0].count_type) || ply_float(fp[0].type) ||
        (fp[0].name != "vertex_indices" && fp[0].name != "vertex_index"))
        return std::nullopt;
    out.slot.assign(out.vertex.props.size(), -1);
    int seen[6] = {};
    for (size_t k = 0; k < out.vertex.props.size(); ++k) {
        const Property& p = out.vertex.props[k];
        if (p.count_type != Type::none || is_colour(p.name)) return std::nullopt;
        for (int s = 0; s < 6; ++s)
            if (p.name == std::array{"x", "y", "z", "nx", "ny", "nz"}[size_t(s)]) {
                out.slot[k] = s;
                if (seen[s]++) return std::nullopt;  // named twice
            }
    }
    out.normals = seen[3] || seen[4] || seen[5];
    if (!seen[0] || !seen[1] || !seen[2] || (out.normals && !(seen[3] && seen[4] && seen[5])))
        return std::nullopt;
    return out;
}

/// The mesh of the body, or nullopt where it does not hold exactly what the layout declares.
template <typename Body>
std::optional<Scene> read_mesh(Body body, const Layout& l, const std::string& path) {
    size_t record = 0;
    for (const Property& p : l.vertex.props) record += Body::least_bytes(p.type);
    if (body.room(record) < l.vertex.count) return std::nullopt;  // before allocating
    // The vertices are bounded by the file's size; the triangles also by memory, as
    // Scene::add_mesh bounds them.
    const auto fits = [&](size_t triangles) {
        require_memory(scene_memory_bytes(l.vertex.count, triangles),
                       "a scene of " + std::to_string(triangles) + " triangles");
    };
    std::vector<Vec3f> verts(l.vertex.count), normals(l.normals ? l.vertex.count : 0);
    for (uint64_t v = 0; v < l.vertex.count; ++v) {
        float value[6] = {};
        for (size_t k = 0; k < l.vertex.props.size(); ++k) {
            const Type t = l.vertex.props[k].type;
            if (!(l.slot[k] < 0 ? body.skip(t) : body.read(t, value[l.slot[k]])))
                return std::nullopt;
        }
        if (!body.end_record()) return std::nullopt;
        verts[v] = {value[0], value[1], value[2]};
        // A broken normal falls back to the geometric normal (the zero vector), as assimp's.
        if (l.normals) {
            const Vec3f n{value[3], value[4], value[5]};
            normals[v] = is_finite(n) ? n : Vec3f{0.f};
        }
    }
    const Property& list = l.face.props[0];
    // A face takes at least a count and three indices.
    if (body.room(Body::least_bytes(list.count_type) + 3 * Body::least_bytes(list.type)) <
        l.face.count)
        return std::nullopt;
    fits(l.face.count);  // at least a triangle per face, before allocating them
    std::vector<TriangleIndices> tris;
    tris.reserve(l.face.count);
    std::vector<uint32_t> poly;
    for (uint64_t f = 0; f < l.face.count; ++f) {
        int64_t n = 0;
        if (!body.read(list.count_type, n) || n < 3 ||
            body.room(Body::least_bytes(list.type)) < uint64_t(n))
            return std::nullopt;
        poly.resize(size_t(n));
        for (uint32_t& i : poly) {
            int64_t index = 0;
            if (!body.read(list.type, index) || index < 0 || uint64_t(index) >= l.vertex.count)
                return std::nullopt;
            i = uint32_t(index);
        }
        if (!body.end_record()) return std::nullopt;
        append_fan(poly.data(), poly.size(), tris);
    }
    if (!body.at_end()) return std::nullopt;
    fits(tris.size());
    // As Scene::add_mesh would make it, without copying the arrays.
    Scene scene;
    scene.name = path;
    scene.triangle_material.assign(tris.size(), scene.add_material(Material{}));
    scene.vertices = std::move(verts);
    scene.triangles = std::move(tris);
    scene.normals = std::move(normals);
    return scene;
}

}  // namespace

std::optional<Scene> import_ply_native(const std::string& path) {
    const TextFile file(path);
    const std::string_view text = file.text();
    const std::optional<Layout> l = layout_of(text);
    if (!l) return std::nullopt;
    const std::string_view body = text.substr(l->body);
    using F = Layout::Format;
    if (l->format == F::ascii) return read_mesh(TextBody(body), *l, path);
    return read_mesh(BinaryBody(body, l->format == F::big_endian), *l, path);
}

}  // namespace rtt::detail
