// What the viewer shows and how keys change it, apart from the window: `rtt view` maps GLFW's
// key codes to the characters below, and tests drive the same function without a display.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "rtt/render.h"

namespace rtt::view {

/// What is drawn over the image: nothing, Figure 5b (primary rays RTT answered) or Figure 5c
/// (shadow segments of light 0).
enum class Overlay { none, primary_map, shadow_map };

struct ViewState {
    std::vector<std::string> tracers;  ///< Tracer kinds the keys cycle through (this build's).
    size_t tracer = 0;                 ///< Index into tracers.
    int aa = 1;                        ///< K of the refined frame; moving frames use K = 1.
    bool shadows = true;
    Overlay overlay = Overlay::none;

    const std::string& tracer_kind() const { return tracers[tracer]; }
};

/// What a key asks for beyond changing the state.
enum class KeyEffect { none, rerender, print_camera, reset_camera, screenshot, help, quit };

/// Applies one key (upper-case letters, digits, '+', '-', 27 for escape) to `state`:
/// T next tracer, 1..9 tracer by number, + / - antialiasing (K up to 8), L shadows on/off,
/// M overlay none -> primary map -> shadow map, C print camera, R reset camera, P screenshot,
/// H help, escape quit. W A S D Q E fly (the window reads them while held).
KeyEffect apply_key(int key, ViewState& state);

/// The keys and mouse bindings, for `--help` and the H key.
const char* key_help();

/// The options of one frame: the refined frame, or a moving one (K = 1).
RenderOptions frame_options(const ViewState& state, const Camera& camera, int width, int height,
                            int threads, bool moving);
/// The answer maps the overlay shows (the shadow map of light 0, when shadows are on).
AnswerMaps frame_maps(const ViewState& state, bool has_lights);

/// 8-bit sRGB RGB of the frame with the overlay: the image itself without one (bit for bit what
/// `rtt render` writes), else half the image's brightness plus green where RTT answered and red
/// where it traced.
std::vector<uint8_t> compose_frame(const RenderResult& frame, Overlay overlay);

/// One line of figures for the window title: the tracer kind that made the frame, K, shadows,
/// frame time, Mrays/s per kind and the share of rays RTT answered.
std::string stats_line(const ViewState& state, std::string_view kind, const RenderResult& frame,
                       bool moving);

}  // namespace rtt::view
