// Renders a built-in scene (or a mesh file given as the first argument) with the renderer,
// the way `rtt render` does, and writes the image as a PNG.
#include <rtt/builtin_scenes.h>
#include <rtt/camera.h>
#include <rtt/io.h>
#include <rtt/kdtree.h>
#include <rtt/render.h>
#include <rtt/scene_io.h>
#include <rtt/tracer.h>

#include <cstdio>
#include <exception>
#include <string>

int main(int argc, char** argv) try {
    const std::string source = argc > 1 ? argv[1] : "room";
    const std::string out = argc > 2 ? argv[2] : "render_image.png";
    rtt::Scene scene = rtt::is_builtin_scene(source) ? rtt::make_builtin_scene(source)
                                                     : rtt::load_scene_file(source);
    if (scene.lights.empty())
        scene.lights.push_back(
            rtt::make_point_light(scene.camera ? scene.camera->position
                                               : rtt::default_camera_for(scene.bounds()).position,
                                  scene.bounds(), 1));
    const rtt::KdTree tree = rtt::build_kdtree(scene);
    const auto tracer = rtt::make_tracer("rtt", scene, tree);

    rtt::RenderOptions options;
    options.camera = scene.camera.value_or(rtt::default_camera_for(scene.bounds()));
    options.width = 320;
    options.height = 240;
    options.aa = 2;
    const rtt::RenderResult image = rtt::render(scene, *tracer, options);
    rtt::write_png(out, image.width, image.height, 3, rtt::encode_srgb8(image.pixels));
    std::printf("%s: %zu triangles, %llu primary rays (%llu answered by RTT) -> %s\n",
                source.c_str(), scene.triangle_count(),
                (unsigned long long)image.stats.primary.trace.rays,
                (unsigned long long)image.stats.primary.rtt.answered, out.c_str());
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "render_image: %s\n", e.what());
    return 1;
}
