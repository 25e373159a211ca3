// libFuzzer target: the values `rtt render` parses from its command line. The first byte picks
// the parser, the rest is the text:
//   0  --camera  parse_camera; an accepted camera must give finite unit ray directions that
//                spread over the image, every tracer must agree through it on a small closed
//                box scene (fuzz_trace.h), and render() must not misbehave.
//   1  --size    parse_size, then RenderOptions::validate with K from the text's length.
//   2  --light   parse_vec3; an accepted light must be finite, make a valid scene light, and
//                render the box through it.
#include <cmath>
#include <cstdint>
#include <string>

#include "cli_values.h"
#include "fuzz_trace.h"
#include "fuzz_util.h"
#include "rtt/camera.h"
#include "rtt/kdtree.h"
#include "rtt/render.h"
#include "rtt/tracer.h"

namespace {

using rtt::fuzz::require;

/// A closed box of 12 triangles around the origin, with its tree and a tracer, built once.
struct BoxScene {
    rtt::Scene scene;
    rtt::KdTree tree;
    std::unique_ptr<rtt::Tracer> tracer;

    BoxScene() {
        const std::vector<rtt::Vec3f> v = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                           {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
        const std::vector<rtt::TriangleIndices> t = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7},
                                                     {0, 1, 5}, {0, 5, 4}, {3, 6, 2}, {3, 7, 6},
                                                     {0, 4, 7}, {0, 7, 3}, {1, 2, 6}, {1, 6, 5}};
        scene.add_mesh(v, t, scene.add_material({}));
        tree = rtt::build_kdtree(scene);
        tracer = rtt::make_tracer("rtt", scene, tree);
    }
};

const BoxScene& box() {
    static const BoxScene b;
    return b;
}

rtt::RenderResult render_box(const rtt::Scene& scene, const rtt::Camera& camera) {
    rtt::RenderOptions opt;
    opt.camera = camera;
    opt.width = 6;
    opt.height = 5;
    opt.threads = 1;
    opt.max_depth = 1;
    opt.hits_buffer = opt.shadow_buffer = true;
    return rtt::render(scene, *box().tracer, opt);
}

void fuzz_camera(const std::string& text) {
    const rtt::Camera cam = rtt::parse_camera(text);
    const rtt::CameraRays rays(cam, 7, 5, 2);  // throws rtt::Error for a degenerate camera
    const rtt::Vec3f corner_a = rays.direction(0, 0, 0, 0), corner_b = rays.direction(6, 4, 1, 1);
    for (const rtt::Vec3f& d : {corner_a, corner_b}) {
        require(rtt::is_finite(d), "accepted camera gives a non-finite ray direction");
        require(std::fabs(rtt::length(d) - 1.f) < 1e-4f, "ray direction is not unit length");
    }
    // Opposite corners of the image must look different ways unless the field of view is too
    // narrow to show in float (then they may round to the same direction).
    if (cam.fovy_deg >= 1.f)
        require(!(corner_a == corner_b), "accepted camera sends every ray the same way");
    rtt::differential::AgreementView view;
    view.camera = cam;
    view.lights = {{0.5f, 0.5f, 0.5f}, cam.position};
    rtt::fuzz::compare_all(box().scene, box().tree, view);
    rtt::Scene lit = box().scene;
    lit.lights.push_back(rtt::make_point_light(cam.position, lit.bounds(), 1));
    const rtt::RenderResult r = render_box(lit, cam);
    require(r.pixels.size() == 30 && r.hits.size() == 30, "render output size");
    (void)rtt::encode_srgb8(r.pixels);
}

void fuzz_size(const std::string& text) {
    int w = 0, h = 0;
    rtt::parse_size(text, w, h);
    rtt::RenderOptions opt;
    opt.width = w;
    opt.height = h;
    opt.aa = int(text.size() % 20) - 2;
    opt.hits_buffer = opt.shadow_buffer = true;
    opt.validate(1);
    require(w >= 1 && h >= 1 && w <= rtt::max_image_side && h <= rtt::max_image_side,
            "validate accepted a size out of range");
}

void fuzz_light(const std::string& text) {
    const rtt::Vec3f p = rtt::parse_vec3(text, "--light");
    require(rtt::is_finite(p), "accepted light position is not finite");
    rtt::Scene lit = box().scene;
    lit.lights.push_back(rtt::make_point_light(p, lit.bounds(), 1));
    rtt::validate(lit);  // a parsed light must always make a valid scene light
    const rtt::RenderResult r = render_box(lit, rtt::Camera{{3, 2, 4}, {0, 0, 0}, {0, 1, 0}, 60});
    (void)rtt::encode_srgb8(r.pixels);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1 || size > 512) return 0;
    const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
    rtt::fuzz::expect_only_rtt_errors([&] {
        switch (data[0] % 3) {
            case 0:
                fuzz_camera(text);
                break;
            case 1:
                fuzz_size(text);
                break;
            default:
                fuzz_light(text);
                break;
        }
    });
    return 0;
}
