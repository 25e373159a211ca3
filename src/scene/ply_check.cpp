// Structural check of PLY files before assimp reads them.
//
// assimp 5.2's PLY reader does not notice a file that ends early: an ASCII file cut inside the
// face list comes back with the last complete face repeated, one cut inside the vertex list
// with zeros and one-index "faces", and a binary one with indices read from past the end of
// its buffer. Walking the element layout the header declares is cheap and catches all three.
// The header is parsed strictly because assimp 5.2 never returns on some malformed ones.
#include <algorithm>

#include "scene/importers.h"
#include "scene/ply_types.h"
#include "scene/text_reader.h"

namespace rtt::detail {
namespace {

struct Property {
    int size = 0;        ///< Bytes of a scalar, or of each list item.
    int count_size = 0;  ///< Bytes of a list's count; 0 for a scalar.
    bool count_signed = false;
};

struct Element {
    std::string name;
    uint64_t count = 0;
    std::vector<Property> props;
};

[[noreturn]] void truncated(const std::string& path, const Element& e, uint64_t i) {
    throw Error(path, 0,
                "truncated PLY: the file ends in " + e.name + " " + std::to_string(i) + " of " +
                    std::to_string(e.count));
}

/// Reads a list count of `size` bytes at `p` (binary), in the file's byte order.
int64_t read_count(const unsigned char* p, const Property& prop, bool big_endian) {
    uint64_t v = 0;
    for (int k = 0; k < prop.count_size; ++k)
        v |= uint64_t(p[big_endian ? prop.count_size - 1 - k : k]) << (8 * k);
    if (prop.count_signed && prop.count_size < 8 && (v >> (8 * prop.count_size - 1)) & 1)
        return int64_t(v) - (int64_t(1) << (8 * prop.count_size));  // sign-extend
    return int64_t(v);
}

}  // namespace

PlyCheck check_ply_structure(const std::string& path) {
    PlyCheck out;
    const TextFile file(path);
    const std::string_view text = file.text();
    TextParser p{path};
    std::vector<Element> elements;
    std::string format;
    size_t pos = 0;
    std::vector<size_t> unknown_lines;  // where each unknown header line starts
    // Header: one keyword line at a time up to "end_header".
    for (int line = 1;; ++line) {
        const size_t end = text.find('\n', pos);
        if (end == std::string::npos) throw Error(path, 0, "PLY header without end_header");
        Tokens tk;
        split_tokens(std::string_view(text).substr(pos, end - pos), tk);
        const size_t line_start = pos;
        pos = end + 1;
        p.line = line;
        // Strict: assimp 5.2 loops forever on some malformed headers (one started "ply}").
        if (line == 1) {
            if (tk.size() != 1 || tk[0] != "ply") p.fail("a PLY file starts with a line \"ply\"");
            continue;
        }
        if (tk.empty() || tk[0] == "comment" || tk[0] == "obj_info") continue;
        if (tk[0] == "end_header") break;
        if (tk[0] == "format") {
            if (tk.size() < 2 || (tk[1] != "ascii" && tk[1] != "binary_little_endian" &&
                                  tk[1] != "binary_big_endian"))
                p.fail("unknown PLY format");
            format = std::string(tk[1]);
        } else if (tk[0] == "element") {
            if (tk.size() < 3) p.fail("element needs a name and a count");
            const int64_t count = p.integer(tk[2]);
            if (count < 0) p.fail("negative element count");
            elements.push_back({std::string(tk[1]), uint64_t(count), {}});
        } else if (tk[0] == "property") {
            if (elements.empty()) p.fail("property before any element");
            Property prop;
            if (tk.size() >= 5 && tk[1] == "list") {
                prop.count_size = int(ply_size(ply_type(tk[2])));
                prop.count_signed = ply_signed_integer(ply_type(tk[2]));
                prop.size = int(ply_size(ply_type(tk[3])));
            } else if (tk.size() >= 3) {
                prop.size = int(ply_size(ply_type(tk[1])));
            }
            if (prop.size == 0 || (tk[1] == "list" && prop.count_size == 0))
                p.fail("bad property line");
            elements.back().props.push_back(prop);
        } else {
            // A line that is no PLY keyword (exporters write "Created by ..."): read as a
            // comment (PlyCheck::repaired), with a warning.
            out.warnings.push_back(path + ":" + std::to_string(line) +
                                   ": unknown PLY header line '" + one_line(std::string(tk[0])) +
                                   "' read as a comment");
            unknown_lines.push_back(line_start);
        }
    }
    if (format.empty()) throw Error(path, 0, "PLY header without a format line");
    if (!unknown_lines.empty()) {
        out.repaired.reserve(text.size() + 8 * unknown_lines.size());
        size_t copied = 0;
        for (const size_t start : unknown_lines) {
            out.repaired.append(text, copied, start - copied);
            out.repaired += "comment ";
            copied = start;
        }
        out.repaired.append(text, copied, std::string::npos);
    }
    p.line = 0;
    if (format == "ascii") {
        // Count whitespace-separated values: a list is its count followed by that many items.
        Tokens tk;
        split_tokens(std::string_view(text).substr(pos), tk);
        size_t t = 0;
        for (const Element& e : elements) {
            // A record without properties has no values: do not walk a huge count of them.
            if (e.props.empty()) continue;
            for (uint64_t i = 0; i < e.count; ++i)
                for (const Property& prop : e.props) {
                    if (t >= tk.size()) truncated(path, e, i);
                    if (prop.count_size == 0) {
                        ++t;
                        continue;
                    }
                    const int64_t n = p.integer(tk[t++]);
                    if (n < 0)
                        p.fail("negative list length in " + e.name + " " + std::to_string(i));
                    if (uint64_t(n) > tk.size() - t) truncated(path, e, i);
                    t += size_t(n);
                }
        }
        return out;
    }
    const bool big = format == "binary_big_endian";
    const auto* data = reinterpret_cast<const unsigned char*>(text.data());
    uint64_t at = pos;
    for (const Element& e : elements) {
        bool has_list = false;
        uint64_t fixed = 0;
        for (const Property& prop : e.props) {
            has_list = has_list || prop.count_size > 0;
            fixed += prop.count_size > 0 ? prop.count_size : prop.size;
        }
        // Every record takes at least `fixed` bytes: refuse impossible counts without looping.
        if (fixed > 0 && e.count > (text.size() - at) / fixed)
            truncated(path, e, (text.size() - at) / fixed);
        if (!has_list) {
            at += e.count * fixed;
            continue;
        }
        for (uint64_t i = 0; i < e.count; ++i)
            for (const Property& prop : e.props) {
                if (prop.count_size == 0) {
                    at += uint64_t(prop.size);
                    continue;
                }
                if (at + uint64_t(prop.count_size) > text.size()) truncated(path, e, i);
                const int64_t n = read_count(data + at, prop, big);
                at += uint64_t(prop.count_size);
                if (n < 0) p.fail("negative list length in " + e.name + " " + std::to_string(i));
                if (uint64_t(n) >
                    (text.size() - std::min<uint64_t>(at, text.size())) / uint64_t(prop.size))
                    truncated(path, e, i);
                at += uint64_t(n) * uint64_t(prop.size);
            }
        if (at > text.size()) truncated(path, e, e.count);
    }
    return out;
}

}  // namespace rtt::detail
