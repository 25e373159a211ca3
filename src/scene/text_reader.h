// Line and number reading shared by rtt's own text mesh readers (OBJ, MTL, OFF).
// Numbers go through std::from_chars, which rounds correctly, so a float written with
// "%.9g" reads back bit for bit (assimp's fast_atof does not: see import_obj.cpp).
#pragma once

#include <charconv>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "core/large_arrays.h"
#include "rtt/error.h"
#include "rtt/math.h"
#include "scene/importers.h"

namespace rtt::detail {

using Tokens = std::vector<std::string_view>;

/// A file's bytes, read in one call into an array of its size on huge pages
/// (core/large_arrays.h). A string stream grown by doubling, then 4 KiB pages faulted one by
/// one, were most of loading a 34 MB OBJ (docs/benchmarks.md, "First image"). What a size does
/// not cover (no size: a pipe; a file still growing) is appended in blocks.
class TextFile {
public:
    explicit TextFile(const std::string& path) {
        std::ifstream in(path, std::ios::binary);
        if (!in) throw Error(path, 0, "cannot open");
        std::error_code ec;
        if (const auto size = std::filesystem::file_size(path, ec); !ec) {
            bytes_.resize(size_t(size));
            in.read(bytes_.data(), std::streamsize(size));
            bytes_.resize(size_t(in.gcount()));
        }
        char block[1 << 16];
        while (in.read(block, sizeof block) || in.gcount() > 0)
            bytes_.insert(bytes_.end(), block, block + in.gcount());
        if (in.bad()) throw Error(path, 0, "cannot read");
    }
    std::string_view text() const { return {bytes_.data(), bytes_.size()}; }

private:
    large_vector<char> bytes_;
};

/// Splits at spaces, tabs, carriage returns and newlines into `out` (cleared first).
inline void split_tokens(std::string_view line, Tokens& out) {
    out.clear();
    size_t i = 0;
    const auto blank = [&](size_t k) {
        return line[k] == ' ' || line[k] == '\t' || line[k] == '\r' || line[k] == '\n';
    };
    while (i < line.size()) {
        while (i < line.size() && blank(i)) ++i;
        const size_t b = i;
        while (i < line.size() && !blank(i)) ++i;
        if (i > b) out.push_back(line.substr(b, i - b));
    }
}

/// Calls `fn(tokens, line_number)` for every non-blank logical line of `text`: '#' comments
/// stripped and, when `join_backslash`, a line ending in '\' joined with the next (OBJ).
template <typename Fn>
void for_each_line(std::string_view text, bool join_backslash, Fn&& fn) {
    std::string joined;
    Tokens tokens;
    int line = 0, first_line = 0;
    size_t pos = text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;  // skip a UTF-8 byte order mark
    while (pos < text.size()) {
        size_t end = text.find('\n', pos);
        if (end == std::string::npos) end = text.size();
        std::string_view raw(text.data() + pos, end - pos);
        pos = end + 1;
        ++line;
        if (const size_t hash = raw.find('#'); hash != std::string_view::npos)
            raw = raw.substr(0, hash);
        while (!raw.empty() && (raw.back() == '\r' || raw.back() == ' ' || raw.back() == '\t'))
            raw.remove_suffix(1);
        if (join_backslash && !raw.empty() && raw.back() == '\\') {
            if (joined.empty()) first_line = line;
            raw.remove_suffix(1);
            joined.append(raw).push_back(' ');
            continue;
        }
        if (!joined.empty()) {
            joined.append(raw);
            raw = joined;
        } else {
            first_line = line;
        }
        split_tokens(raw, tokens);
        if (!tokens.empty()) fn(tokens, first_line);
        joined.clear();
    }
    if (!joined.empty()) {
        split_tokens(joined, tokens);
        if (!tokens.empty()) fn(tokens, first_line);
    }
}

/// Number parsing with "path:line: message" errors.
struct TextParser {
    const std::string& path;
    int line = 0;

    [[noreturn]] void fail(const std::string& message) const { throw Error(path, line, message); }

    float number(std::string_view t) const {
        std::string_view s = t;
        if (s.size() > 1 && s[0] == '+') s.remove_prefix(1);  // from_chars refuses a leading '+'
        float v = 0.f;
        const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        if (ec == std::errc::result_out_of_range)
            fail("number out of float range: " + std::string(t));
        if (ec != std::errc() || end != s.data() + s.size())
            fail("expected a number, got '" + one_line(std::string(t)) + "'");
        return v;
    }

    /// tokens[first], [first + 1], [first + 2] as a point, which must be finite unless
    /// `any_value` (mesh vertices: load_mesh_file drops the triangles on NaN or infinite ones).
    Vec3f point(const Tokens& tk, size_t first, const char* what, bool any_value = false) const {
        if (tk.size() < first + 3) fail(std::string("expected 3 coordinates for ") + what);
        const Vec3f v{number(tk[first]), number(tk[first + 1]), number(tk[first + 2])};
        if (!any_value && !is_finite(v))
            fail(std::string(what) + " has a NaN or infinite coordinate");
        return v;
    }

    int64_t integer(std::string_view t) const {
        int64_t v = 0;
        const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
        if (ec != std::errc() || end != t.data() + t.size())
            fail("expected an integer, got '" + one_line(std::string(t)) + "'");
        return v;
    }
};

}  // namespace rtt::detail
