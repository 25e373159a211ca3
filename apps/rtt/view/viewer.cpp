#include "view/viewer.h"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>

#include "cli_values.h"
#include "output_set.h"
#include "render/progress.h"
#include "render_job.h"
#include "rtt/error.h"
#include "rtt/io.h"
#include "rtt/kdtree.h"
#include "rtt/render.h"
#include "view/background_kdtree.h"
#include "view/orbit_camera.h"
#include "view/view_state.h"

namespace rtt::view {
namespace {

using Clock = std::chrono::steady_clock;

/// GLFW reports errors through a callback; the last one explains a failed call.
std::string last_glfw_error;

/// The window, its GL context and GLFW itself, released in that order.
class Window {
public:
    Window(int width, int height, const std::string& title) {
        glfwSetErrorCallback([](int, const char* text) { last_glfw_error = text; });
        if (!glfwInit())
            throw Error("cannot open a window: " + last_glfw_error +
                        " (on a machine without a display, run under xvfb-run)");
        glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
        window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
        if (!window_) {
            glfwTerminate();
            throw Error("cannot open a window: " + last_glfw_error);
        }
        glfwMakeContextCurrent(window_);
        glfwSwapInterval(0);  // frames are slower than the display: never wait for it
    }
    ~Window() {
        glfwDestroyWindow(window_);
        glfwTerminate();
    }
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;
    GLFWwindow* get() const { return window_; }

private:
    GLFWwindow* window_ = nullptr;
};

/// What the input callbacks change between frames.
struct Input {
    OrbitCamera* camera = nullptr;
    ViewState* state = nullptr;
    std::vector<KeyEffect> effects;  ///< Keys pressed since the last frame.
    bool camera_moved = false;
    bool dragging_orbit = false, dragging_pan = false;
    double last_x = 0, last_y = 0;
    int window_height = 1;
};

Input& input_of(GLFWwindow* w) {
    return *static_cast<Input*>(glfwGetWindowUserPointer(w));
}

/// GLFW's key code as apply_key's character (letters upper case), or 0.
int key_char(int key) {
    if (key >= GLFW_KEY_A && key <= GLFW_KEY_Z) return 'A' + (key - GLFW_KEY_A);
    if (key >= GLFW_KEY_0 && key <= GLFW_KEY_9) return '0' + (key - GLFW_KEY_0);
    switch (key) {
        case GLFW_KEY_EQUAL:
        case GLFW_KEY_KP_ADD:
            return '+';
        case GLFW_KEY_MINUS:
        case GLFW_KEY_KP_SUBTRACT:
            return '-';
        case GLFW_KEY_ESCAPE:
            return 27;
        default:
            return 0;
    }
}

void install_callbacks(GLFWwindow* window) {
    glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int) {
        if (action != GLFW_PRESS) return;
        Input& in = input_of(w);
        // Flying keys (W A S D Q E) act while held: fly() reads them each frame.
        const KeyEffect effect = apply_key(key_char(key), *in.state);
        // Camera keys act at once: a drag later in the same batch of events must not move the
        // camera before C prints it.
        if (effect == KeyEffect::print_camera) {
            std::printf("--camera %s\n", camera_string(in.camera->camera()).c_str());
            std::fflush(stdout);
        } else if (effect == KeyEffect::reset_camera) {
            in.camera->reset();
            in.camera_moved = true;
        } else if (effect != KeyEffect::none) {
            in.effects.push_back(effect);
        }
    });
    glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int) {
        Input& in = input_of(w);
        const bool down = action == GLFW_PRESS;
        if (button == GLFW_MOUSE_BUTTON_LEFT) in.dragging_orbit = down;
        if (button == GLFW_MOUSE_BUTTON_RIGHT || button == GLFW_MOUSE_BUTTON_MIDDLE)
            in.dragging_pan = down;
        glfwGetCursorPos(w, &in.last_x, &in.last_y);
    });
    glfwSetCursorPosCallback(window, [](GLFWwindow* w, double x, double y) {
        Input& in = input_of(w);
        const float dx = float(x - in.last_x), dy = float(y - in.last_y);
        in.last_x = x;
        in.last_y = y;
        if (in.dragging_orbit) {
            in.camera->orbit(-dx * 0.005f, dy * 0.005f);
            in.camera_moved = true;
        } else if (in.dragging_pan) {
            const float h = float(std::max(in.window_height, 1));
            in.camera->pan(-dx / h, dy / h);
            in.camera_moved = true;
        }
    });
    glfwSetScrollCallback(window, [](GLFWwindow* w, double, double dy) {
        Input& in = input_of(w);
        in.camera->dolly(float(dy));
        in.camera_moved = true;
    });
}

/// Moves the camera by the flying keys held down, for `seconds` of flight.
bool fly(GLFWwindow* w, OrbitCamera& camera, double seconds) {
    const auto held = [&](int key) { return glfwGetKey(w, key) == GLFW_PRESS ? 1.f : 0.f; };
    const float forward = held(GLFW_KEY_W) - held(GLFW_KEY_S);
    const float right = held(GLFW_KEY_D) - held(GLFW_KEY_A);
    const float up = held(GLFW_KEY_E) - held(GLFW_KEY_Q);
    if (forward == 0.f && right == 0.f && up == 0.f) return false;
    const bool fast = glfwGetKey(w, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS;
    // A tenth of the scene per second (a whole scene with shift), at most a frame of 0.1 s.
    const float step = float(std::min(seconds, 0.1)) * (fast ? 1.f : 0.1f);
    camera.fly(forward * step, right * step, up * step);
    return true;
}

/// Draws RGB rows (top row first) at the window's lower left corner, pixel for pixel.
void draw(const std::vector<uint8_t>& rgb, int width, int height, int fb_width, int fb_height) {
    glViewport(0, 0, fb_width, fb_height);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glClearColor(0.f, 0.f, 0.f, 1.f);
    glClear(GL_COLOR_BUFFER_BIT);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    // GL's rows go bottom-up: draw the image's last row first via a negative zoom from the top.
    glRasterPos2f(-1.f, 1.f);
    glPixelZoom(1.f, -1.f);
    glDrawPixels(width, height, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
}

/// The window's pixels as drawn (top row first): what a screenshot shows.
std::vector<uint8_t> read_back(int width, int height, int fb_height) {
    std::vector<uint8_t> bottom_up(size_t(width) * size_t(height) * 3);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, fb_height - height, width, height, GL_RGB, GL_UNSIGNED_BYTE, bottom_up.data());
    std::vector<uint8_t> rgb(bottom_up.size());
    const size_t row = size_t(width) * 3;
    for (int y = 0; y < height; ++y)
        std::copy_n(bottom_up.begin() + std::ptrdiff_t(size_t(height - 1 - y) * row), row,
                    rgb.begin() + std::ptrdiff_t(size_t(y) * row));
    return rgb;
}

Overlay parse_overlay(const std::string& text) {
    if (text == "none") return Overlay::none;
    if (text == "primary") return Overlay::primary_map;
    if (text == "shadow") return Overlay::shadow_map;
    throw Error("--overlay must be none, primary or shadow, not '" + text + "'");
}

/// The tracers the T key cycles through: this build's, without brute force (seconds per frame
/// on any real scene) unless it was asked for; the chosen one first.
std::vector<std::string> cycled_tracers(const std::string& chosen) {
    std::vector<std::string> out{chosen};
    for (const std::string& k : tracer_kinds())
        if (k != chosen && k != "brute") out.push_back(k);
    return out;
}

}  // namespace

void run_viewer(const ViewerOptions& o) {
    // Options and the screenshot's folder before any work.
    int width = 0, height = 0;
    parse_size(o.size, width, height);
    if (width < 1 || height < 1 || width > max_image_side || height > max_image_side)
        throw Error("--size " + o.size + " out of range (each side 1.." +
                    std::to_string(max_image_side) + ")");
    if (o.aa < 1 || o.aa > 8) throw Error("--aa must be 1..8 in the viewer");
    if (o.frames < 0) throw Error("--frames must be at least 0");
    if (o.threads < 0) throw Error("--threads must be at least 1");
    std::optional<Camera> given;
    if (!o.camera.empty()) given = parse_camera(o.camera);
    std::vector<Vec3f> light_positions;
    for (const std::string& l : o.lights) light_positions.push_back(parse_vec3(l, "--light"));
    // `auto`, `rtt render`'s default, is what the viewer does for its default kind anyway:
    // bvh stands in until the kd-tree is built.
    const std::string kind =
        o.tracer.empty() || o.tracer == auto_tracer ? cli::default_tracer_kind() : o.tracer;
    check_tracer_kind(kind);
    ViewState state;
    state.tracers = cycled_tracers(kind);
    state.aa = o.aa;
    state.shadows = o.shadows;
    state.overlay = parse_overlay(o.overlay);
    const std::string screenshot_path = o.screenshot.empty() ? "view.png" : o.screenshot;
    if (!o.screenshot.empty()) {
        cli::OutputSet check;
        check.add("--screenshot", o.screenshot, {".png"});
        check.check_writable();
    }

    cli::LoadedScene loaded = [&] {
        const render_detail::ProgressBar progress(0, !o.quiet, "loading the scene");
        return cli::load_scene_quietly(o.scene);
    }();
    cli::print_warnings(loaded.scene);
    Scene& scene = loaded.scene;
    const Bbox3f bounds = scene.bounds();
    OrbitCamera camera(cli::starting_camera(loaded, given),
                       bounds.empty() ? 2.f : length(bounds.hi - bounds.lo));
    const bool lit_from_eye = cli::set_up_lights(scene, light_positions, camera.camera().position);
    validate(scene);
    // The kd-tree, for the kinds that read it (bvh and Embree need none). Interactive frames do
    // not wait for it: the first comes from `bvh`, whatever can show the scene soonest
    // (docs/benchmarks.md, "First image"); the kd-tree starts building after that frame (the
    // two builds would share the cores) and takes over once built. Scripted runs (--frames)
    // wait for it, so their frames are the chosen kind's. Declared before the tracers, which
    // refer to it.
    std::optional<BackgroundKdTree> tree;
    const KdTree no_tree;
    std::map<std::string, std::unique_ptr<Tracer>> tracers;  // made when first shown
    // The tracers, made when first shown; the kind the kd-tree was started for comes with it.
    const auto made = [&](const std::string& k, const KdTree& t) -> const Tracer& {
        std::unique_ptr<Tracer>& tracer = tracers[k];
        if (!tracer && tree && &t == tree->ready()) tracer = tree->take_tracer(k);
        if (!tracer) tracer = make_tracer(k, scene, t);
        return *tracer;
    };
    // The tracer a frame of kind k uses now, and the name the title shows for it.
    struct Shown {
        const Tracer* tracer;
        std::string name;
        bool standing_in;  ///< bvh while k's kd-tree builds.
    };
    const auto tracer_for = [&](const std::string& k) -> Shown {
        if (!tracer_uses_kdtree(k)) return {&made(k, no_tree), k, false};
        const KdTree* built = nullptr;
        if (o.frames > 0) {
            if (!tree) tree.emplace(scene, k);
            built = tree->ready();
            if (!built) {
                const render_detail::ProgressBar progress(0, !o.quiet, "building the kd-tree");
                built = &tree->wait();
            }
        } else if (tree) {
            built = tree->ready();
        }
        if (built) return {&made(k, *built), k, false};
        return {&made("bvh", no_tree), "bvh while " + k + "'s kd-tree builds", true};
    };

    Window window(width, height, "rtt view");
    Input input;
    input.camera = &camera;
    input.state = &state;
    glfwSetWindowUserPointer(window.get(), &input);
    install_callbacks(window.get());
    if (!o.quiet && o.frames == 0) std::printf("%s\n", key_help());

    std::vector<uint8_t> shown;  // the frame on screen
    int shown_width = 0, shown_height = 0;
    bool refined = false;      // the frame on screen has the chosen K
    bool dirty = true;         // settings changed since it was rendered
    bool standing_in = false;  // the frame on screen is bvh's, the kd-tree still building
    int frames = 0;
    auto last_motion = Clock::now() - std::chrono::seconds(1);
    auto last_frame = Clock::now();
    while (!glfwWindowShouldClose(window.get())) {
        const auto now = Clock::now();
        const double dt = std::chrono::duration<double>(now - last_frame).count();
        last_frame = now;
        bool moved = std::exchange(input.camera_moved, false);
        moved |= fly(window.get(), camera, dt);
        bool save = false;
        for (KeyEffect e : std::exchange(input.effects, {})) {
            switch (e) {
                case KeyEffect::rerender:
                    dirty = true;
                    break;
                case KeyEffect::screenshot:
                    save = true;
                    break;
                case KeyEffect::help:
                    std::printf("%s\n", key_help());
                    break;
                case KeyEffect::quit:
                    glfwSetWindowShouldClose(window.get(), GLFW_TRUE);
                    break;
                case KeyEffect::print_camera:  // handled in the key callback, in event order
                case KeyEffect::reset_camera:
                case KeyEffect::none:
                    break;
            }
        }
        if (moved) last_motion = now;
        if (standing_in && tree && tree->ready()) dirty = true;  // the chosen kind takes over
        // Moving frames at K = 1 until the camera has rested for 0.2 s, then the chosen K once.
        const bool moving = o.frames == 0 && now - last_motion < std::chrono::milliseconds(200);
        int fb_width = 0, fb_height = 0;
        glfwGetFramebufferSize(window.get(), &fb_width, &fb_height);
        input.window_height = fb_height;
        const bool resized = fb_width != shown_width || fb_height != shown_height;
        const bool render_now = o.frames > 0 || moved || dirty || resized || (!moving && !refined);
        if (render_now && fb_width > 0 && fb_height > 0) {
            if (lit_from_eye)
                scene.lights[0] = make_point_light(camera.camera().position, bounds, 1);
            const RenderOptions opt =
                frame_options(state, camera.camera(), fb_width, fb_height, o.threads, moving);
            const Shown shown_by = tracer_for(state.tracer_kind());
            const RenderResult frame =
                render(scene, *shown_by.tracer, opt, frame_maps(state, !scene.lights.empty()));
            standing_in = shown_by.standing_in;
            if (standing_in && !tree) tree.emplace(scene, state.tracer_kind());
            shown = compose_frame(frame, state.overlay);
            shown_width = fb_width;
            shown_height = fb_height;
            refined = !moving;
            dirty = false;
            ++frames;
            const std::string line = stats_line(state, shown_by.name, frame, moving);
            glfwSetWindowTitle(window.get(), line.c_str());
            if (o.frames > 0 && !o.quiet) std::printf("frame %d: %s\n", frames, line.c_str());
        }
        if (!shown.empty()) draw(shown, shown_width, shown_height, fb_width, fb_height);
        const bool last = o.frames > 0 && frames >= o.frames;
        if ((save || (last && !o.screenshot.empty())) && !shown.empty()) {
            const std::vector<uint8_t> pixels = read_back(shown_width, shown_height, fb_height);
            try {
                write_png(screenshot_path, shown_width, shown_height, 3, pixels);
                if (!o.quiet) std::printf("rtt view: wrote %s\n", screenshot_path.c_str());
            } catch (const Error& e) {
                if (last) throw;                                   // the headless run's one output
                std::fprintf(stderr, "rtt view: %s\n", e.what());  // the window stays open
            }
        }
        glfwSwapBuffers(window.get());
        if (last) break;
        // Idle with a refined frame on screen: sleep until something happens (while the kd-tree
        // builds, look for it every 20 ms without taking a core from it).
        if (!moving && refined && !dirty)
            glfwWaitEventsTimeout(standing_in ? 0.02 : 0.1);
        else
            glfwPollEvents();
    }
}

}  // namespace rtt::view
