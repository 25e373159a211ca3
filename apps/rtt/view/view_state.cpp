#include "view/view_state.h"

#include <algorithm>
#include <cstdio>

namespace rtt::view {

/// The largest K the + key reaches: beyond it a frame takes seconds on a desktop.
static constexpr int max_view_aa = 8;

KeyEffect apply_key(int key, ViewState& state) {
    switch (key) {
        case 'T':
            state.tracer = (state.tracer + 1) % state.tracers.size();
            return KeyEffect::rerender;
        case '+':
        case '=':  // the same key without shift on most layouts
            if (state.aa >= max_view_aa) return KeyEffect::none;
            ++state.aa;
            return KeyEffect::rerender;
        case '-':
            if (state.aa <= 1) return KeyEffect::none;
            --state.aa;
            return KeyEffect::rerender;
        case 'L':
            state.shadows = !state.shadows;
            return KeyEffect::rerender;
        case 'M':
            state.overlay = state.overlay == Overlay::none          ? Overlay::primary_map
                            : state.overlay == Overlay::primary_map ? Overlay::shadow_map
                                                                    : Overlay::none;
            return KeyEffect::rerender;
        case 'C':
            return KeyEffect::print_camera;
        case 'R':
            return KeyEffect::reset_camera;
        case 'P':
            return KeyEffect::screenshot;
        case 'H':
            return KeyEffect::help;
        case 27:
            return KeyEffect::quit;
        default:
            break;
    }
    if (key >= '1' && key <= '9' && size_t(key - '1') < state.tracers.size()) {
        state.tracer = size_t(key - '1');
        return KeyEffect::rerender;
    }
    return KeyEffect::none;
}

const char* key_help() {
    return "Mouse: left drag orbits about the target, right (or middle) drag pans, the wheel\n"
           "dollies. Keys: W/S A/D E/Q fly forward/back, left/right, up/down (shift: faster);\n"
           "T next tracer, 1-9 tracer by number; + / - antialiasing K; L shadows on/off;\n"
           "M overlay: none, primary RTT map (green answered, red traced), shadow map of\n"
           "light 0; C prints the camera as a --camera value; R resets the camera;\n"
           "P saves a screenshot (--screenshot, else view.png); H this help; Esc quits.\n"
           "While the camera moves frames use K = 1; the chosen K follows when it stops.";
}

RenderOptions frame_options(const ViewState& state, const Camera& camera, int width, int height,
                            int threads, bool moving) {
    RenderOptions opt;
    opt.camera = camera;
    opt.width = width;
    opt.height = height;
    opt.aa = moving ? 1 : state.aa;
    opt.threads = threads;
    opt.shadows = state.shadows;
    return opt;
}

AnswerMaps frame_maps(const ViewState& state, bool has_lights) {
    AnswerMaps maps;
    maps.primary = state.overlay == Overlay::primary_map;
    maps.shadow_light =
        state.overlay == Overlay::shadow_map && state.shadows && has_lights ? 0 : -1;
    return maps;
}

std::vector<uint8_t> compose_frame(const RenderResult& frame, Overlay overlay) {
    std::vector<uint8_t> rgb = encode_srgb8(frame.pixels);
    const std::vector<uint8_t>& map =
        overlay == Overlay::primary_map ? frame.primary_map : frame.shadow_map;
    if (overlay == Overlay::none || map.empty()) return rgb;
    for (size_t p = 0; p < map.size(); ++p) {
        const int answered = map[p];  // 0 traced .. 255 answered (shadows: 128 from a list)
        rgb[3 * p + 0] = uint8_t(rgb[3 * p + 0] / 2 + (255 - answered) / 2);
        rgb[3 * p + 1] = uint8_t(rgb[3 * p + 1] / 2 + answered / 2);
        rgb[3 * p + 2] = uint8_t(rgb[3 * p + 2] / 2);
    }
    return rgb;
}

std::string stats_line(const ViewState& state, std::string_view kind, const RenderResult& frame,
                       bool moving) {
    const RenderStats& s = frame.stats;
    const auto share = [](const KindStats& k) {
        return k.trace.rays ? 100.0 * double(k.rtt.answered) / double(k.trace.rays) : 0.0;
    };
    const uint64_t rays = s.primary.trace.rays + s.shadow.trace.rays + s.secondary.trace.rays;
    char line[320];
    std::snprintf(line, sizeof line,
                  "rtt view | %.*s | K=%d%s | shadows %s | %.0f ms, %.1f Mrays/s | primary %.1f, "
                  "shadow %.1f Mrays/s per thread | RTT answered %.0f%% primary, %.0f%% shadow",
                  int(kind.size()), kind.data(), moving ? 1 : state.aa, moving ? " (moving)" : "",
                  state.shadows ? "on" : "off", s.wall_seconds * 1e3,
                  s.wall_seconds > 0 ? double(rays) / s.wall_seconds * 1e-6 : 0.0,
                  s.primary.mrays_per_second(), s.shadow.mrays_per_second(), share(s.primary),
                  share(s.shadow));
    return line;
}

}  // namespace rtt::view
