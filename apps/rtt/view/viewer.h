// `rtt view`: a window that renders the scene with the chosen tracer on all cores while the user
// moves the camera (GLFW + OpenGL; built only when CMake finds GLFW, see apps/rtt/view/).
#pragma once

#include <string>
#include <vector>

#include "scene_args.h"

namespace rtt::view {

struct ViewerOptions {
    cli::SceneArgs scene;
    std::string camera;               ///< --camera; empty = the scene's or a default one.
    std::vector<std::string> lights;  ///< --light x,y,z each; empty = the scene's lights.
    std::string size = "960x720";     ///< Window size WxH (the frames' size, pixel for pixel).
    int aa = 1;
    std::string tracer;  ///< Empty = the default tracer.
    int threads = 0;
    int max_depth = 4;
    bool shadows = true;
    std::string overlay = "none";  ///< none, primary, shadow.
    int frames = 0;                ///< > 0: render this many frames, then close (headless use).
    std::string screenshot;        ///< PNG written by the P key, and after the last frame.
    bool quiet = false;
};

/// Opens the window and runs until it is closed (or `frames` are shown). Throws rtt::Error for
/// bad options, a scene that fails to load, or no display ("cannot open a window: ...").
void run_viewer(const ViewerOptions& options);

}  // namespace rtt::view
