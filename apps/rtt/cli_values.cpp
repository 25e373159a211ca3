#include "cli_values.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "rtt/error.h"

namespace rtt {
namespace {

std::string_view trimmed(std::string_view s) {
    const size_t b = s.find_first_not_of(" \t");
    if (b == std::string_view::npos) return {};
    return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

/// One float of a comma-separated list; std::from_chars is correctly rounded and ignores the
/// locale. Returns false unless the whole item is a number within float range.
bool parse_float(std::string_view item, float& out) {
    std::string_view s = trimmed(item);
    if (s.size() > 1 && s[0] == '+' && s[1] != '-') s.remove_prefix(1);  // from_chars refuses '+'
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return !s.empty() && ec == std::errc() && end == s.data() + s.size();
}

}  // namespace

Vec3f parse_vec3(const std::string& text, const std::string& what) {
    std::vector<float> v;
    size_t start = 0;
    // Every comma separates two items, so "1,2,3," has an empty fourth item and is refused.
    for (;;) {
        const size_t comma = text.find(',', start);
        const std::string_view item = std::string_view(text).substr(
            start, comma == std::string::npos ? std::string::npos : comma - start);
        float f = 0.f;
        if (!parse_float(item, f))
            throw Error(what + ": '" + std::string(item) + "' is not a number (expected x,y,z)");
        if (!std::isfinite(f)) throw Error(what + ": NaN or infinite value in '" + text + "'");
        v.push_back(f);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    if (v.size() != 3)
        throw Error(what + ": expected 3 comma-separated numbers x,y,z, got '" + text + "'");
    return {v[0], v[1], v[2]};
}

void parse_size(const std::string& text, int& width, int& height) {
    const size_t x = text.find_first_of("xX");
    const auto number = [](std::string_view s, int& out) {
        const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
        return !s.empty() && ec == std::errc() && end == s.data() + s.size();
    };
    if (x == std::string::npos || !number(std::string_view(text).substr(0, x), width) ||
        !number(std::string_view(text).substr(x + 1), height))
        throw Error("--size: expected WxH with whole numbers, e.g. 640x480, got '" + text + "'");
}

Camera parse_camera(const std::string& text) {
    std::vector<float> v;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        try {
            size_t used = 0;
            const float f = std::stof(item, &used);
            if (used != item.size() && item.find_first_not_of(" \t", used) != std::string::npos)
                throw Error("");
            v.push_back(f);
        } catch (...) {
            throw Error("camera: '" + item +
                        "' is not a number (expected px,py,pz,tx,ty,tz,ux,uy,uz,fovy)");
        }
    }
    if (v.size() != 10)
        throw Error(
            "camera: expected 10 comma-separated numbers px,py,pz,tx,ty,tz,ux,uy,uz,fovy, got " +
            std::to_string(v.size()));
    for (float f : v)
        if (!std::isfinite(f)) throw Error("camera: NaN or infinite value");
    return Camera{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}, v[9]};
}

namespace {

/// One camera of a JSON camera path: the 10 numbers of --camera as an array, or an object with
/// the scene format's keys (position, target, up = [0, 1, 0], fovy = 60).
Camera json_camera(const nlohmann::json& j) {
    const auto numbers = [](const nlohmann::json& a, size_t count, const char* what) {
        if (!a.is_array() || a.size() != count)
            throw Error(std::string(what) + ": expected " + std::to_string(count) + " numbers");
        std::vector<float> v;
        for (const nlohmann::json& x : a) {
            if (!x.is_number() || !std::isfinite(x.get<double>()))
                throw Error(std::string(what) + ": expected finite numbers");
            v.push_back(x.get<float>());
        }
        return v;
    };
    if (j.is_array()) {
        const std::vector<float> v = numbers(j, 10, "camera");
        return Camera{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}, v[9]};
    }
    if (!j.is_object() || !j.contains("position") || !j.contains("target"))
        throw Error("a camera is 10 numbers or an object with \"position\" and \"target\"");
    for (const auto& item : j.items())
        if (item.key() != "position" && item.key() != "target" && item.key() != "up" &&
            item.key() != "fovy")
            throw Error("unknown camera key \"" + item.key() + "\"");
    Camera c;
    const std::vector<float> p = numbers(j["position"], 3, "position"),
                             t = numbers(j["target"], 3, "target");
    c.position = {p[0], p[1], p[2]};
    c.target = {t[0], t[1], t[2]};
    if (j.contains("up")) {
        const std::vector<float> u = numbers(j["up"], 3, "up");
        c.up = {u[0], u[1], u[2]};
    }
    if (j.contains("fovy")) {
        if (!j["fovy"].is_number()) throw Error("fovy: expected a number");
        c.fovy_deg = j["fovy"].get<float>();
    }
    return c;
}

}  // namespace

std::vector<Camera> read_camera_path(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw Error(path + ": cannot open the camera path");
    std::vector<Camera> cameras;
    // A JSON list when the file starts with '['; one camera per line otherwise.
    in >> std::ws;
    if (in.peek() == '[') {
        nlohmann::json list;
        try {
            list = nlohmann::json::parse(in);
        } catch (const nlohmann::json::exception& e) {
            throw Error(path + ": not valid JSON: " + e.what());
        }
        for (size_t i = 0; i < list.size(); ++i) {
            try {
                cameras.push_back(json_camera(list[i]));
            } catch (const Error& e) {
                throw Error(path + ": camera " + std::to_string(i + 1) + ": " + e.what());
            }
        }
        if (cameras.empty()) throw Error(path + ": no camera in the camera path");
        return cameras;
    }
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        const size_t first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#') continue;
        if (line.back() == '\r') line.pop_back();
        try {
            cameras.push_back(parse_camera(line));
        } catch (const Error& e) {
            throw Error(path, number, e.what());
        }
    }
    if (cameras.empty()) throw Error(path + ": no camera in the camera path");
    return cameras;
}

std::string frame_file_name(const std::string& option, const std::string& pattern, size_t frame,
                            size_t frames) {
    const size_t at = pattern.find('%');
    if (at == std::string::npos) {
        if (frames > 1)
            throw Error(option + ": " + std::to_string(frames) +
                        " frames need a frame number in the file name, as in " +
                        "frame_%04d.png (got '" + pattern + "')");
        return pattern;
    }
    size_t end = at + 1, width = 0;
    if (end < pattern.size() && pattern[end] == '0') ++end;
    if (end < pattern.size() && pattern[end] >= '1' && pattern[end] <= '9')
        width = size_t(pattern[end++] - '0');
    if (end >= pattern.size() || pattern[end] != 'd' || pattern.find('%', end) != std::string::npos)
        throw Error(option + ": '" + pattern +
                    "': the only '%' directive a file name may hold is one %d or %0Nd");
    std::string number = std::to_string(frame);
    if (number.size() < width) number.insert(0, width - number.size(), '0');
    return pattern.substr(0, at) + number + pattern.substr(end + 1);
}

}  // namespace rtt
