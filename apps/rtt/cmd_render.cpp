// `rtt render`: the options of CONVENTIONS ("Command line used by outside checks") and more.
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>

#include "commands.h"
#include "render_job.h"
#include "rtt/camera.h"
#include "rtt/error.h"
#include "rtt/io.h"
#include "rtt/kdtree.h"
#include "rtt/parse.h"
#include "rtt/render.h"
#include "rtt/tracer.h"
#include "stats_report.h"

namespace rtt::cli {
namespace {

std::string joined(const std::vector<std::string>& items) {
    std::string s;
    for (const std::string& i : items) s += (s.empty() ? "" : ", ") + i;
    return s;
}

}  // namespace

std::string default_tracer_kind() {
    const std::vector<std::string> kinds = tracer_kinds();
    for (const char* preferred : {"rtt", "packet", "ray"})
        if (std::find(kinds.begin(), kinds.end(), preferred) != kinds.end()) return preferred;
    return kinds.empty() ? "ray" : kinds.front();
}

RenderJobResult run_render_job(const RenderJob& job) {
    // Everything checkable without the scene first: bad options fail fast.
    RenderOptions opt;
    parse_size(job.size, opt.width, opt.height);
    opt.aa = job.aa;
    opt.max_depth = job.max_depth;
    if (job.threads < 0) throw Error("--threads must be at least 1");
    opt.threads = job.threads;
    std::vector<Vec3f> light_positions;
    for (const std::string& l : job.lights) light_positions.push_back(parse_vec3(l, "--light"));
    if (light_positions.size() > max_lights)
        throw Error(std::to_string(light_positions.size()) + " lights given; at most " +
                    std::to_string(max_lights) + " are supported");
    std::optional<Camera> camera;
    if (!job.camera.empty()) camera = parse_camera(job.camera);
    const std::string tracer_kind = job.tracer.empty() ? default_tracer_kind() : job.tracer;
    const std::vector<std::string> kinds = tracer_kinds();
    if (std::find(kinds.begin(), kinds.end(), tracer_kind) == kinds.end())
        throw Error("unknown tracer '" + tracer_kind + "' (this build has: " + joined(kinds) + ")");
    opt.hits_buffer = !job.hits.empty();
    opt.shadow_buffer = !job.shadows.empty();
    opt.primary_map = !job.map_primary.empty();
    if (job.map_light < 0) throw Error("--rtt-map-light must be at least 0");
    opt.shadow_map_light = job.map_shadow.empty() ? -1 : job.map_light;
    opt.progress = !job.quiet;
    {
        // Size, K, depth and threads before loading anything; the map light once lights are known.
        RenderOptions early = opt;
        early.shadow_map_light = -1;
        early.validate(light_positions.size());
    }

    LoadedScene loaded = load_scene(job.scene);
    Scene& scene = loaded.scene;
    const Bbox3f bounds = scene.bounds();
    if (camera)
        opt.camera = *camera;
    else if (scene.camera && !loaded.from_mesh)
        opt.camera = *scene.camera;
    else
        opt.camera = default_camera_for(bounds);
    if (!light_positions.empty()) {
        scene.lights.clear();
        for (const Vec3f& p : light_positions)
            scene.lights.push_back(make_point_light(p, bounds, light_positions.size()));
    } else if (scene.lights.empty()) {
        // A mesh (or a scene without lights) is lit from the eye: everything visible is lit.
        scene.lights.push_back(make_point_light(opt.camera.position, bounds, 1));
    }
    validate(scene);
    opt.validate(scene.lights.size());

    RenderJobResult out;
    out.scene_label = loaded.label;
    out.triangles = scene.triangle_count();
    out.tracer = tracer_kind;
    const auto build_start = std::chrono::steady_clock::now();
    const KdTree tree = build_kdtree(scene);
    out.kd_build_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - build_start).count();
    out.kd_stats = tree.stats;
    const std::unique_ptr<Tracer> tracer = make_tracer(tracer_kind, scene, tree);
    out.result = render(scene, *tracer, opt);
    const RenderResult& r = out.result;

    if (!job.image.empty()) write_png(job.image, r.width, r.height, 3, encode_srgb8(r.pixels));
    const auto spp = uint32_t(r.aa * r.aa);
    if (!job.hits.empty())
        write_hit_buffer(job.hits, HitBuffer{uint32_t(r.width), uint32_t(r.height), spp, r.hits});
    if (!job.shadows.empty())
        write_shadow_buffer(job.shadows, ShadowBuffer{uint32_t(r.width), uint32_t(r.height), spp,
                                                      uint32_t(scene.lights.size()), r.shadows});
    if (!job.map_primary.empty()) write_png(job.map_primary, r.width, r.height, 1, r.primary_map);
    if (!job.map_shadow.empty()) write_png(job.map_shadow, r.width, r.height, 1, r.shadow_map);
    if (!job.stats_json.empty()) write_stats_json(job.stats_json, job, out);
    if (job.stats) print_stats(stdout, out);
    return out;
}

void add_render_command(CLI::App& app) {
    auto job = std::make_shared<RenderJob>();
    CLI::App* cmd = app.add_subcommand(
        "render", "Render a mesh or scene (PNG, hit/shadow buffers, statistics)");
    cmd->footer(
        "Rays, sample order and buffer layouts follow CONVENTIONS (see README, \"Command line\").\n"
        "--mesh renders geometry only, with a grey material; without --camera the camera looks at\n"
        "the bounding box from a diagonal, and without --light one omni light sits at the camera.\n"
        "Each --light x,y,z is a white omni light of intensity 0.5 * d^2 / n (d = scene "
        "bounding-box\n"
        "diagonal, n = number of --light options), so images are neither black nor blown out\n"
        "whatever the scene's units. --camera and --light replace a scene's own.");
    add_scene_options(*cmd, job->scene);
    cmd->add_option("--camera", job->camera,
                    "Pinhole camera px,py,pz,tx,ty,tz,ux,uy,uz,fovy (degrees)");
    cmd->add_option("--size", job->size, "Image size WxH (each side 1..16384)")
        ->capture_default_str();
    cmd->add_option("--aa", job->aa, "Antialiasing: K x K samples per pixel, K in 1..16")
        ->capture_default_str();
    cmd->add_option("--light", job->lights,
                    "Omni light at x,y,z (repeatable, at most 32; replaces the scene's)");
    cmd->add_option(
        "--tracer", job->tracer,
        "Tracer: " + joined(tracer_kinds()) + " (default: " + default_tracer_kind() + ")");
    CLI::Option* threads =
        cmd->add_option("--threads", job->threads, "Worker threads (default: all cores)");
    cmd->add_option("--max-depth", job->max_depth, "Mirror reflection depth (0 = no reflections)")
        ->capture_default_str();
    cmd->add_option("-o,--output", job->image, "Write the image as PNG");
    cmd->add_option("--hits", job->hits, "Write the RTTH hit buffer (closest triangle per sample)");
    cmd->add_option("--shadows", job->shadows,
                    "Write the RTTS shadow buffer (visible lights per sample)");
    cmd->add_flag("--stats", job->stats,
                  "Print rays, time and Mrays/s per kind (primary, shadow, secondary)");
    cmd->add_option("--stats-json", job->stats_json, "Write the statistics as JSON");
    cmd->add_flag("-q,--quiet", job->quiet, "No progress bar");
    cmd->add_option("--rtt-map-primary", job->map_primary,
                    "PNG of the primary samples RTT answered (white) or traced (black), Figure 5b");
    cmd->add_option("--rtt-map-shadow", job->map_shadow,
                    "PNG of one light's shadow segments: white answered with an empty list, grey "
                    "answered from a list, black traced, Figure 5c");
    cmd->add_option("--rtt-map-light", job->map_light, "Light shown by --rtt-map-shadow")
        ->capture_default_str();
    cmd->callback([job, threads] {
        // 0 means "all cores" inside; on the command line it is a mistake.
        if (threads->count() > 0 && job->threads < 1) throw Error("--threads must be at least 1");
        run_render_job(*job);
    });
}

}  // namespace rtt::cli
