// The viewer (`rtt view`): its camera motions and key handling without a window, and the window
// itself under Xvfb (a screenshot equals `rtt render` of the same camera, bit for bit).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "cli_run.h"
#include "cli_values.h"
#include "rtt/builtin_scenes.h"
#include "rtt/camera.h"
#include "rtt/error.h"
#include "rtt/kdtree.h"
#include "view/background_kdtree.h"
#include "view/orbit_camera.h"
#include "view/view_state.h"

namespace rtt::test {
namespace {

const Camera start{{1.f, 2.f, 3.f}, {0.f, 0.5f, 0.f}, {0.f, 1.f, 0.f}, 50.f};

float distance_to_target(const Camera& c) {
    return length(c.position - c.target);
}

TEST(ViewCamera, StartsBitForBitAtTheGivenCameraAndResetsToIt) {
    view::OrbitCamera camera(start, 10.f);
    EXPECT_EQ(camera.camera().position, start.position);
    EXPECT_EQ(camera.camera().target, start.target);
    camera.orbit(0.3f, 0.2f);
    camera.fly(0.1f, 0.f, 0.f);
    EXPECT_NE(camera.camera().position, start.position);
    camera.reset();
    EXPECT_EQ(camera.camera().position, start.position);
    EXPECT_EQ(camera.camera().target, start.target);
}

TEST(ViewCamera, OrbitKeepsTheTargetAndDistanceAndStopsShortOfTheUpAxis) {
    view::OrbitCamera camera(start, 10.f);
    const float d = distance_to_target(start);
    camera.orbit(1.f, 0.f);
    EXPECT_EQ(camera.camera().target, start.target);
    EXPECT_NEAR(distance_to_target(camera.camera()), d, 1e-5f * d);
    EXPECT_NEAR(camera.camera().position.y, start.position.y, 1e-5f);  // yaw is about up
    camera.orbit(0.f, 0.2f);  // positive pitch raises the eye
    EXPECT_GT(camera.camera().position.y, start.position.y);
    camera.orbit(0.f, 10.f);  // far past the pole: clamped a degree short of it
    const Vec3f view = normalize(camera.camera().target - camera.camera().position);
    EXPECT_LT(std::fabs(view.y), std::cos(0.5f * 3.14159265f / 180.f));
    EXPECT_NO_THROW(CameraRays(camera.camera(), 8, 8, 1));
}

TEST(ViewCamera, PanDollyAndFlyMoveAsNamed) {
    view::OrbitCamera camera(start, 10.f);
    const float d = distance_to_target(start);
    camera.dolly(1.f);
    EXPECT_NEAR(distance_to_target(camera.camera()), 0.9f * d, 1e-5f * d);
    camera.dolly(-1.f);
    EXPECT_NEAR(distance_to_target(camera.camera()), d, 1e-5f * d);
    camera.dolly(1e6f);  // never onto the target
    EXPECT_GT(distance_to_target(camera.camera()), 0.f);
    camera.reset();
    camera.pan(0.f, 0.5f);  // half the view's height upwards: eye and target move together
    EXPECT_GT(camera.camera().target.y, start.target.y);
    EXPECT_NEAR(distance_to_target(camera.camera()), d, 1e-5f * d);
    camera.reset();
    camera.fly(0.1f, 0.f, 0.f);  // a tenth of the scene size towards the target
    EXPECT_NEAR(length(camera.camera().position - start.position), 1.f, 1e-5f);
    EXPECT_LT(distance_to_target(camera.camera()), d + 1e-5f);
}

TEST(ViewCamera, CameraStringGivesTheCameraBackExactly) {
    view::OrbitCamera camera(start, 10.f);
    camera.orbit(0.123f, -0.0456f);
    camera.pan(0.01f, 0.02f);
    const Camera back = parse_camera(view::camera_string(camera.camera()));
    EXPECT_EQ(back.position, camera.camera().position);
    EXPECT_EQ(back.target, camera.camera().target);
    EXPECT_EQ(back.up, camera.camera().up);
    EXPECT_EQ(back.fovy_deg, camera.camera().fovy_deg);
}

TEST(ViewKeys, ChangeTheStateAsTheHelpSays) {
    view::ViewState s;
    s.tracers = {"rtt", "packet16", "embree"};
    EXPECT_EQ(view::apply_key('T', s), view::KeyEffect::rerender);
    EXPECT_EQ(s.tracer_kind(), "packet16");
    view::apply_key('3', s);
    EXPECT_EQ(s.tracer_kind(), "embree");
    EXPECT_EQ(view::apply_key('9', s), view::KeyEffect::none);  // no ninth tracer
    view::apply_key('T', s);
    EXPECT_EQ(s.tracer_kind(), "rtt");                          // wraps
    EXPECT_EQ(view::apply_key('-', s), view::KeyEffect::none);  // K stays >= 1
    for (int i = 0; i < 20; ++i) view::apply_key('+', s);
    EXPECT_EQ(s.aa, 8);
    view::apply_key('L', s);
    EXPECT_FALSE(s.shadows);
    view::apply_key('M', s);
    EXPECT_EQ(s.overlay, view::Overlay::primary_map);
    view::apply_key('M', s);
    EXPECT_EQ(s.overlay, view::Overlay::shadow_map);
    view::apply_key('M', s);
    EXPECT_EQ(s.overlay, view::Overlay::none);
    EXPECT_EQ(view::apply_key('C', s), view::KeyEffect::print_camera);
    EXPECT_EQ(view::apply_key('R', s), view::KeyEffect::reset_camera);
    EXPECT_EQ(view::apply_key('P', s), view::KeyEffect::screenshot);
    EXPECT_EQ(view::apply_key(27, s), view::KeyEffect::quit);
    EXPECT_EQ(view::apply_key('W', s), view::KeyEffect::none);  // flying is read while held
}

TEST(ViewFrames, MovingFramesUseOneSampleAndShadowsOffTracesNoSegments) {
    view::ViewState s;
    s.tracers = {"rtt"};
    s.aa = 3;
    EXPECT_EQ(view::frame_options(s, start, 64, 48, 0, true).aa, 1);
    EXPECT_EQ(view::frame_options(s, start, 64, 48, 0, false).aa, 3);
    s.overlay = view::Overlay::shadow_map;
    EXPECT_EQ(view::frame_maps(s, true).shadow_light, 0);
    EXPECT_EQ(view::frame_maps(s, false).shadow_light, -1);
    EXPECT_FALSE(view::frame_maps(s, true).primary);

    const Scene scene = make_builtin_scene("room");
    const KdTree tree = build_kdtree(scene);
    const auto tracer = make_tracer("rtt", scene, tree);
    s.overlay = view::Overlay::none;
    RenderOptions with = view::frame_options(s, *scene.camera, 64, 48, 1, false);
    s.shadows = false;
    RenderOptions without = view::frame_options(s, *scene.camera, 64, 48, 1, false);
    const RenderResult lit = render(scene, *tracer, with),
                       unshadowed = render(scene, *tracer, without);
    EXPECT_GT(lit.stats.shadow.trace.rays, 0u);
    EXPECT_EQ(unshadowed.stats.shadow.trace.rays, 0u);
    EXPECT_NE(lit.pixels, unshadowed.pixels);  // the room has shadows
    // Without an overlay the frame is the image rtt render writes.
    EXPECT_EQ(view::compose_frame(lit, view::Overlay::none), encode_srgb8(lit.pixels));
    without.shadow_buffer = true;
    EXPECT_THROW(without.validate(scene.lights.size()), Error);
    // The title names the kind that made the frame (bvh standing in while the kd-tree builds).
    EXPECT_NE(view::stats_line(s, "bvh while rtt's kd-tree builds", lit, false)
                  .find("| bvh while rtt's kd-tree builds |"),
              std::string::npos);
}

TEST(ViewFrames, TheKdTreeBuiltOnItsOwnThreadIsTheOneBuiltInPlace) {
    const Scene scene = make_builtin_scene("room");
    view::BackgroundKdTree background(scene, "rtt");
    const KdTree& tree = background.wait();
    EXPECT_EQ(background.ready(), &tree);
    const KdTree in_place = build_kdtree(scene);
    EXPECT_EQ(tree.nodes.size(), in_place.nodes.size());
    EXPECT_EQ(tree.leaf_triangles, in_place.leaf_triangles);
    EXPECT_EQ(tree.bounds.lo, in_place.bounds.lo);
    EXPECT_EQ(tree.bounds.hi, in_place.bounds.hi);
    // The tracer made with it, of the kind asked for only, renders what one made here does.
    EXPECT_EQ(background.take_tracer("packet16"), nullptr);
    const std::unique_ptr<Tracer> tracer = background.take_tracer("rtt");
    ASSERT_NE(tracer, nullptr);
    EXPECT_EQ(tracer->name(), "rtt");
    EXPECT_EQ(background.take_tracer("rtt"), nullptr);  // once
    view::ViewState s;
    s.tracers = {"rtt"};
    const RenderOptions opt = view::frame_options(s, *scene.camera, 64, 48, 1, false);
    EXPECT_EQ(render(scene, *tracer, opt).pixels,
              render(scene, *make_tracer("rtt", scene, in_place), opt).pixels);
}

#ifdef RTT_TEST_HAVE_VIEWER
/// The headless window runs need Xvfb (Debian's xvfb, installed by scripts/install-deps.sh).
bool have_xvfb() {
    return std::system("command -v Xvfb >/dev/null 2>&1") == 0;
}
// Mesa's GL driver is loaded and unloaded by GLFW and leaves a few allocations LeakSanitizer
// cannot name (frames in an unloaded module): the sanitizer build checks leaks everywhere else.
// Each window run gets an X server of its own, on a display the server picked and announced
// when ready, stopped after the run (tests/headless.sh).
const std::string xvfb =
    "env ASAN_OPTIONS=detect_leaks=0 bash '" + std::string(RTT_TEST_DATA_DIR) + "/../headless.sh' ";

TEST(ViewWindow, ScreenshotEqualsRenderOfTheSameCamera) {
    if (!have_xvfb()) GTEST_SKIP() << "Xvfb not installed";
    TempDir dir("view_window");
    const std::string camera = "--camera 2.5,1.2,3.1,0,0.8,0,0,1,0,55";
    // bvh: a kind the viewer builds no kd-tree for, and its packets' image is every kind's; auto:
    // `rtt render`'s default, accepted by the viewer too.
    for (const char* options : {"--aa 1", "--aa 2 --tracer packet16", "--aa 1 --tracer bvh",
                                "--aa 1 --tracer auto", "--aa 1 --no-shadows"}) {
        SCOPED_TRACE(options);
        const std::string cmd = xvfb + "'" + std::string(RTT_CLI_PATH) + "' view --scene room " +
                                camera + " --size 96x72 --frames 2 -q --screenshot '" +
                                dir.file("view.png") + "' " + options;
        ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
        if (std::string(options).find("no-shadows") != std::string::npos) {
            // No render option turns shadows off: the screenshot must differ from the shadowed one.
            ASSERT_EQ(run_cli(dir, "render --scene room " + camera + " --size 96x72 -q -o r.png")
                          .exit_code,
                      0);
            EXPECT_NE(read_text(dir.file("view.png")), read_text(dir.file("r.png")));
            continue;
        }
        const std::string aa = std::string(options).substr(0, 6);
        ASSERT_EQ(run_cli(dir, "render --scene room " + camera + " --size 96x72 -q -o r.png " + aa)
                      .exit_code,
                  0);
        EXPECT_EQ(read_text(dir.file("view.png")), read_text(dir.file("r.png")));
    }
}

TEST(ViewWindow, KeysAndMouseMoveTheCamera) {
    if (!have_xvfb() || std::system("command -v xdotool >/dev/null 2>&1") != 0)
        GTEST_SKIP() << "Xvfb or xdotool not installed";
    TempDir dir("view_input");
    const std::string out = dir.file("out.txt");
    const std::string start_camera = "2,1.5,3,0,0.2,0,0,1,0,50";
    const std::string cmd = xvfb + "bash '" + std::string(RTT_TEST_DATA_DIR) +
                            "/../view_input.sh' '" + std::string(RTT_CLI_PATH) + "' '" + out +
                            "' --mesh '" + std::string(RTT_TEST_DATA_DIR) +
                            "/render_mesh.obj' --camera " + start_camera;
    ASSERT_EQ(std::system(cmd.c_str()), 0) << read_text(out);
    // Two cameras printed: the starting one exactly, then one the drag, wheel and W key moved.
    std::istringstream lines(read_text(out));
    std::vector<Camera> cameras;
    for (std::string line; std::getline(lines, line);)
        if (line.rfind("--camera ", 0) == 0) cameras.push_back(parse_camera(line.substr(9)));
    ASSERT_EQ(cameras.size(), 2u) << read_text(out);
    const Camera given = parse_camera(start_camera);
    EXPECT_EQ(cameras[0].position, given.position);
    EXPECT_EQ(cameras[0].target, given.target);
    EXPECT_NE(cameras[1].position, given.position);
    EXPECT_LT(length(cameras[1].position - cameras[1].target),
              length(given.position - given.target));  // the wheel and W moved closer
}

TEST(ViewWindow, BadInputFailsBeforeOpeningAWindow) {
    TempDir dir("view_bad");
    const auto fails = [&](const std::string& args, const std::string& message) {
        const RunResult r = run_cli(dir, args);
        EXPECT_EQ(r.exit_code, 1) << args;
        EXPECT_NE(r.err.find(message), std::string::npos) << args << ": " << r.err;
    };
    fails("view --scene room --aa 9", "--aa must be 1..8");
    fails("view --scene room --overlay sideways", "--overlay must be none, primary or shadow");
    fails("view --scene room --screenshot /nonexistent/dir/v.png", "--screenshot");
    fails("view --scene room --screenshot v.jpg", "--screenshot");
    fails("view --scene nosuchscene", "nosuchscene");
    // No display at all: one clear line, not a crash.
    const char* display = std::getenv("DISPLAY");
    const std::string saved = display ? display : "";
    unsetenv("DISPLAY");
    unsetenv("WAYLAND_DISPLAY");
    fails("view --scene room --size 32x32 --frames 1 -q", "cannot open a window");
    if (display) setenv("DISPLAY", saved.c_str(), 1);
}
#endif

}  // namespace
}  // namespace rtt::test
