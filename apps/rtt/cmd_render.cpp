// `rtt render`: the options of CONVENTIONS ("Command line used by outside checks") and more.
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include "cli_values.h"
#include "commands.h"
#include "mpi_render.h"
#include "output_set.h"
#include "render/progress.h"
#include "render_job.h"
#include "rtt/camera.h"
#include "rtt/error.h"
#include "rtt/io.h"
#include "rtt/kdtree.h"
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

/// A map (one byte per pixel) as PNG or PGM, by extension (OutputSet checked it).
void write_grey(const std::string& path, const std::string& ext, int w, int h,
                const std::vector<uint8_t>& map) {
    if (ext == ".pgm")
        write_pnm(path, w, h, 1, map);
    else
        write_png(path, w, h, 1, map);
}

/// -o by extension: PNG / PPM (8-bit sRGB), PFM (linear float), EXR (linear float RGB and the
/// --aov layers: depth.Z, N.X/Y/Z, triangle.id, rtt.Y; README, "Outputs").
void write_image(const std::string& path, const std::string& ext, const RenderJob& job,
                 const Scene& scene, const RenderResult& r) {
    if (ext == ".png" || ext == ".ppm") {
        const std::vector<uint8_t> srgb = encode_srgb8(r.pixels);
        if (ext == ".png")
            write_png(path, r.width, r.height, 3, srgb);
        else
            write_pnm(path, r.width, r.height, 3, srgb);
        return;
    }
    if (ext == ".pfm") return write_pfm(path, r.width, r.height, r.pixels);
    const size_t n = r.pixels.size();
    std::vector<float> rgb[3];
    for (int c = 0; c < 3; ++c) {
        rgb[c].resize(n);
        for (size_t i = 0; i < n; ++i) rgb[c][i] = r.pixels[i][c];
    }
    std::vector<ExrChannel> channels = {{"R", rgb[0], {}}, {"G", rgb[1], {}}, {"B", rgb[2], {}}};
    if (job.wants_aov("depth")) channels.push_back({"depth.Z", r.depth, {}});
    std::vector<float> normal[3];
    if (job.wants_aov("normal")) {
        // Unit geometric normal of the first sample's triangle, as CONVENTIONS orders its
        // vertices; 0 on a miss.
        for (auto& v : normal) v.assign(n, 0.f);
        for (size_t i = 0; i < n; ++i) {
            if (r.first_triangle[i] == invalid_triangle) continue;
            const TriangleIndices& t = scene.triangles[r.first_triangle[i]];
            const Vec3f c = cross(scene.vertices[t[1]] - scene.vertices[t[0]],
                                  scene.vertices[t[2]] - scene.vertices[t[0]]);
            const float len = length(c);
            if (!(len > 0.f)) continue;
            for (int k = 0; k < 3; ++k) normal[k][i] = c[k] / len;
        }
        channels.push_back({"N.X", normal[0], {}});
        channels.push_back({"N.Y", normal[1], {}});
        channels.push_back({"N.Z", normal[2], {}});
    }
    if (job.wants_aov("triangle")) channels.push_back({"triangle.id", {}, r.first_triangle});
    std::vector<float> answered;
    if (job.wants_aov("rtt")) {
        answered.resize(n);
        for (size_t i = 0; i < n; ++i) answered[i] = float(r.primary_map[i]) / 255.f;
        channels.push_back({"rtt.Y", answered, {}});
    }
    write_exr(path, r.width, r.height, channels);
}

}  // namespace

const std::vector<std::string>& image_extensions() {
    static const std::vector<std::string> e = {".png", ".exr", ".pfm", ".ppm"};
    return e;
}

const std::vector<std::string>& aov_names() {
    static const std::vector<std::string> a = {"depth", "normal", "triangle", "rtt"};
    return a;
}

bool has_no_output(const RenderJob& j) {
    return j.image.empty() && j.hits.empty() && j.shadows.empty() && j.map_primary.empty() &&
           j.map_shadow.empty() && j.stats_json.empty() && !j.stats;
}

std::string default_image_path(const SceneArgs& scene) {
    const std::string stem = std::filesystem::path(scene.source()).stem().string();
    return (stem.empty() ? std::string("render") : stem) + ".png";
}

namespace {
bool has_kind(const char* kind) {
    const std::vector<std::string> kinds = tracer_kinds();
    return std::find(kinds.begin(), kinds.end(), kind) != kinds.end();
}
}  // namespace

std::string default_tracer_kind() {
    for (const char* preferred : {"rtt", "packet", "ray"})
        if (has_kind(preferred)) return preferred;
    const std::vector<std::string> kinds = tracer_kinds();
    return kinds.empty() ? "ray" : kinds.front();
}

bool has_auto_tracer() {
    return has_kind("bvh") && has_kind("rtt");
}

std::string default_render_tracer() {
    return has_auto_tracer() ? std::string(auto_tracer) : default_tracer_kind();
}

namespace {

/// Writes one frame's outputs (names from the job's patterns) through `outputs`.
void write_outputs(OutputSet& outputs, const RenderJob& job, size_t frame, size_t frames,
                   const Scene& scene, const RenderJobResult& out) {
    const RenderResult& r = out.result;
    const auto name = [&](const char* option, const std::string& pattern) {
        return job.camera_path.empty() ? pattern : frame_file_name(option, pattern, frame, frames);
    };
    const auto spp = uint32_t(r.aa * r.aa);
    if (!job.image.empty())
        outputs.write(name("-o", job.image), [&](const std::string& tmp) {
            write_image(tmp, extension_of(job.image), job, scene, r);
        });
    if (!job.hits.empty())
        outputs.write(name("--hits", job.hits), [&](const std::string& tmp) {
            write_hit_buffer(tmp, HitBuffer{uint32_t(r.width), uint32_t(r.height), spp, r.hits});
        });
    if (!job.shadows.empty())
        outputs.write(name("--shadows", job.shadows), [&](const std::string& tmp) {
            write_shadow_buffer(tmp, ShadowBuffer{uint32_t(r.width), uint32_t(r.height), spp,
                                                  uint32_t(scene.lights.size()), r.shadows});
        });
    if (!job.map_primary.empty())
        outputs.write(name("--rtt-map-primary", job.map_primary), [&](const std::string& tmp) {
            write_grey(tmp, extension_of(job.map_primary), r.width, r.height, r.primary_map);
        });
    if (!job.map_shadow.empty())
        outputs.write(name("--rtt-map-shadow", job.map_shadow), [&](const std::string& tmp) {
            write_grey(tmp, extension_of(job.map_shadow), r.width, r.height, r.shadow_map);
        });
    if (!job.stats_json.empty())
        outputs.write(name("--stats-json", job.stats_json),
                      [&](const std::string& tmp) { write_stats_json(tmp, job, out); });
    outputs.commit();
}

}  // namespace

/// The file's camera `index` (decimal digits), or an error naming how many it has.
Camera file_camera(const Scene& scene, const std::string& index) {
    const size_t n = scene.file_cameras.size();
    size_t i = 0;
    const auto [end, ec] = std::from_chars(index.data(), index.data() + index.size(), i);
    if (ec != std::errc() || end != index.data() + index.size() || i >= n)
        throw Error("--camera " + index + ": " + scene.name + " has " + std::to_string(n) +
                    (n == 1 ? " camera" : " cameras") +
                    (n == 0 ? "" : " (0 to " + std::to_string(n - 1) + "; --list-cameras)"));
    return scene.file_cameras[i].camera;
}

/// --list-cameras: one line per camera of the file, as --camera takes it.
void list_cameras(const RenderJob& job) {
    const LoadedScene loaded = load_scene_quietly(job.scene);
    const Scene& scene = loaded.scene;
    if (scene.file_cameras.empty()) {
        std::printf("%s defines no camera\n", loaded.label.c_str());
        return;
    }
    for (size_t i = 0; i < scene.file_cameras.size(); ++i) {
        const FileCamera& f = scene.file_cameras[i];
        const Camera& c = f.camera;
        std::printf("%zu \"%s\": --camera %.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", i,
                    f.name.c_str(), c.position.x, c.position.y, c.position.z, c.target.x,
                    c.target.y, c.target.z, c.up.x, c.up.y, c.up.z, c.fovy_deg);
    }
}

RenderJobResult run_render_job(const RenderJob& job) {
    // Everything checkable without the scene first: bad options fail fast.
    RenderOptions opt;
    parse_size(job.size, opt.width, opt.height);
    opt.aa = job.aa;
    opt.region = job.region;
    opt.max_depth = job.max_depth;
    if (job.threads < 0) throw Error("--threads must be at least 1");
    opt.threads = job.threads;
    std::vector<Vec3f> light_positions;
    for (const std::string& l : job.lights) light_positions.push_back(parse_vec3(l, "--light"));
    if (light_positions.size() > max_lights)
        throw Error(std::to_string(light_positions.size()) + " lights given; at most " +
                    std::to_string(max_lights) + " are supported");
    std::optional<Camera> camera;
    // --camera N picks a camera of the file once it is loaded; 10 numbers give one here.
    const bool camera_index =
        !job.camera.empty() && job.camera.find_first_not_of("0123456789") == std::string::npos;
    if (!job.camera.empty() && !camera_index) camera = parse_camera(job.camera);
    const std::string requested = job.tracer.empty() ? default_render_tracer() : job.tracer;
    const bool auto_kind = requested == auto_tracer;
    if (auto_kind && !has_auto_tracer())
        throw Error("--tracer auto needs the bvh and rtt kinds, which this build lacks");
    if (!auto_kind) check_tracer_kind(requested);
    opt.hits_buffer = !job.hits.empty();
    opt.shadow_buffer = !job.shadows.empty();
    AnswerMaps maps;
    maps.primary = !job.map_primary.empty();
    if (job.map_light < 0) throw Error("--rtt-map-light must be at least 0");
    maps.shadow_light = job.map_shadow.empty() ? -1 : job.map_light;
    opt.progress = !job.quiet;
    for (const std::string& a : job.aovs)
        if (std::find(aov_names().begin(), aov_names().end(), a) == aov_names().end())
            throw Error("--aov: unknown output variable '" + a +
                        "' (known: " + joined(aov_names()) + ")");
    if (!job.aovs.empty() && extension_of(job.image) != ".exr")
        throw Error("--aov writes EXR layers: give -o FILE.exr");
    opt.pixel_hits = job.wants_aov("depth") || job.wants_aov("normal") || job.wants_aov("triangle");
    if (job.wants_aov("rtt")) maps.primary = true;

    std::vector<Camera> path;
    if (!job.camera_path.empty()) {
        if (!job.camera.empty()) throw Error("give --camera or --camera-path, not both");
        path = read_camera_path(job.camera_path);
    }
    const size_t frames = path.empty() ? 1 : path.size();

    // Every destination before any work: names, extensions, folders (of the first and last
    // frame of a camera path: a pattern puts all frames in one folder).
    const auto frame_outputs = [&](size_t frame, OutputSet& outputs) {
        const auto add = [&](const char* option, const std::string& pattern,
                             const std::vector<std::string>& extensions = {}) {
            if (pattern.empty()) return;
            // Names are patterns only for a camera path; otherwise taken as given.
            outputs.add(option,
                        path.empty() ? pattern : frame_file_name(option, pattern, frame, frames),
                        extensions);
        };
        add("-o", job.image, image_extensions());
        add("--hits", job.hits);
        add("--shadows", job.shadows);
        add("--rtt-map-primary", job.map_primary, {".png", ".pgm"});
        add("--rtt-map-shadow", job.map_shadow, {".png", ".pgm"});
        add("--stats-json", job.stats_json);
    };
    const bool writer = mpi_rank() == 0;  // under mpirun, rank 0 writes and reports
    for (size_t frame : {size_t(0), frames - 1}) {
        OutputSet outputs;
        frame_outputs(frame, outputs);
        if (writer) outputs.check_writable();
    }
    // Size, K, depth and threads before loading anything; the map light once lights are known.
    opt.validate(light_positions.size());

    LoadedScene loaded = [&] {
        const render_detail::ProgressBar progress(0, !job.quiet && writer, "loading the scene");
        return load_scene_quietly(job.scene);
    }();
    if (writer) print_warnings(loaded.scene);
    Scene& scene = loaded.scene;
    if (camera_index) camera = file_camera(scene, job.camera);
    const Bbox3f bounds = scene.bounds();
    const Camera start = starting_camera(loaded, camera);
    const auto camera_of = [&](size_t frame) { return path.empty() ? start : path[frame]; };
    opt.camera = camera_of(0);
    // A mesh (or a scene without lights) is lit from the eye: everything visible is lit.
    const bool lit_from_eye = set_up_lights(scene, light_positions, opt.camera.position);
    validate(scene);
    opt.validate(scene.lights.size());
    maps.validate(opt, scene.lights.size());

    // `auto`: RTT once a kd-tree is at hand (loaded, built to be saved, shared under mpirun) or
    // its answer maps are asked for; else frames from `bvh`, whose BVH builds about 4x faster
    // than the kd-tree, until their rays have paid for the kd-tree and RTT's setup (then `rtt`;
    // docs/benchmarks.md, "First image", has the price and the saving). Every kind gives the
    // same hits, so the frames do not change.
    const bool rtt_from_start = !job.tree.load.empty() || !job.tree.save.empty() || maps.primary ||
                                maps.shadow_light >= 0 || mpi_distributed();
    std::string tracer_kind = requested;
    if (auto_kind) tracer_kind = rtt_from_start ? "rtt" : "bvh";

    RenderJobResult out;
    out.scene_label = loaded.label;
    out.triangles = scene.triangle_count();
    out.input_warnings = scene.warning_count;
    out.tracer_auto = auto_kind;
    const auto seconds_since = [](std::chrono::steady_clock::time_point start) {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    KdTree tree;
    std::unique_ptr<Tracer> tracer;
    const auto build_tree = [&] {
        tracer.reset();  // it may refer to the tree replaced here
        const auto start = std::chrono::steady_clock::now();
        {
            const render_detail::ProgressBar progress(
                0, !job.quiet && writer,
                job.tree.load.empty() ? "building the kd-tree" : "loading the kd-tree");
            tree = share_tree(
                scene, [&] { return make_tree(job.tree, scene); }, job.rank_timeout);
        }
        out.kd_build_seconds = seconds_since(start);
        out.kd_loaded = !job.tree.load.empty();
        out.kd_stats = tree.stats;
        out.kd_used = true;
    };
    const auto set_tracer = [&](const std::string& kind) {
        const auto start = std::chrono::steady_clock::now();
        tracer = make_tracer(kind, scene, tree);
        out.tracer_build_seconds = seconds_since(start);
        out.tracer = kind;
    };
    // Tracers with structures of their own (bvh, Embree) need no kd-tree unless asked to
    // save or load one.
    out.kd_used = false;
    if (tracer_uses_kdtree(tracer_kind) || !job.tree.load.empty() || !job.tree.save.empty())
        build_tree();
    set_tracer(tracer_kind);
    // `auto`, once the rays traced so far would have paid for them: the kd-tree and RTT.
    uint64_t bvh_rays = 0;
    opt.progress = opt.progress && writer;
    const auto options_of = [&](RenderOptions o, size_t frame) {
        o.camera = camera_of(frame);
        if (lit_from_eye) scene.lights[0] = make_point_light(o.camera.position, bounds, 1);
        return o;
    };
    // One frame's outputs are written all or none; earlier frames stay.
    const auto write_frame = [&](size_t frame) {
        OutputSet outputs;
        frame_outputs(frame, outputs);
        write_outputs(outputs, job, frame, frames, scene, out);
        if (job.stats) print_stats(stdout, out);
        if (frames > 1 && !job.quiet)
            std::fprintf(stderr, "rtt: frame %zu of %zu done\n", frame + 1, frames);
    };
    if (mpi_distributed() && frames >= size_t(mpi_size())) {
        // Enough frames for every rank: whole frames, no bands (docs/distributed.md).
        RenderOptions frame_opt = opt;
        frame_opt.progress = false;  // one line per finished frame instead
        std::vector<RankStats> ranks;
        render_frames_distributed(
            frames, frame_opt, maps,
            [&](size_t frame) {
                return render(scene, *tracer, options_of(frame_opt, frame), maps);
            },
            [&](size_t frame, RenderResult& r) {
                out.result = std::move(r);
                write_frame(frame);
            },
            &ranks, job.rank_timeout);
        out.ranks = ranks;
        if (job.stats && writer) print_rank_stats(stdout, out.ranks);
        return out;
    }
    for (size_t frame = 0; frame < frames; ++frame) {
        if (auto_kind && !out.kd_used && auto_paid_for_rtt(bvh_rays, out.triangles)) {
            build_tree();
            set_tracer("rtt");
        }
        opt = options_of(opt, frame);
        out.ranks.clear();
        out.result = mpi_distributed() ? render_distributed(scene, *tracer, opt, maps, &out.ranks,
                                                            job.rank_timeout)
                                       : render(scene, *tracer, opt, maps);
        if (writer) write_frame(frame);
        bvh_rays += out.result.stats.rays();
    }
    return out;
}

void add_render_command(CLI::App& app) {
    auto job = std::make_shared<RenderJob>();
    CLI::App* cmd = app.add_subcommand(
        "render", "Render a mesh or scene (PNG, hit/shadow buffers, statistics)");
    cmd->footer(
        "Rays, sample order and buffer layouts follow CONVENTIONS (see README, \"Command line\").\n"
        "--mesh renders the file's geometry and materials (grey where it has none), not its\n"
        "cameras or lights: without --camera the camera looks at the bounding box from a "
        "diagonal,\n"
        "and without --light one omni light sits at the camera. `rtt render FILE` keeps them.\n"
        "Each --light x,y,z is a white omni light of intensity 0.5 * d^2 / n (d = scene "
        "bounding-box\n"
        "diagonal, n = number of --light options), so images are neither black nor blown out\n"
        "whatever the scene's units. --camera and --light replace a scene's own.");
    add_scene_options(*cmd, job->scene);
    add_tree_options(*cmd, job->tree);
    cmd->add_option("--camera", job->camera,
                    "Pinhole camera px,py,pz,tx,ty,tz,ux,uy,uz,fovy (degrees), or N: the "
                    "file's camera N (from 0; --list-cameras)");
    cmd->add_flag("--list-cameras", job->list_cameras,
                  "Print the cameras the scene file defines (as --camera takes them) and exit");
    cmd->add_option("--camera-path", job->camera_path,
                    "Render a sequence: one camera per line (the 10 numbers of --camera; '#' "
                    "comments); output names need a frame number, as in -o frame_%04d.png");
    cmd->add_option("--size", job->size, "Image size WxH (each side 1..16384)")
        ->capture_default_str();
    cmd->add_option("--aa", job->aa, "Antialiasing: K x K samples per pixel, K in 1..16")
        ->capture_default_str();
    cmd->add_option("--region", job->region,
                    "Pixels per side of the regions handed to the tracer as one tile (a multiple "
                    "of 4 up to 256; 0 = 32 at K=1, 8 from K=2 to 8, else 4). RTT "
                    "tries a region as one shaft; results do not depend on it")
        ->capture_default_str();
    cmd->add_option("--light", job->lights,
                    "Omni light at x,y,z (repeatable, at most 32; replaces the scene's)");
    cmd->add_option(
        "--tracer", job->tracer,
        "Tracer: " + joined(tracer_kinds()) +
            (has_auto_tracer()
                 ? ", auto (bvh, whose BVH builds fastest, until its rays have paid for "
                   "the kd-tree, then rtt; rtt when the kd-tree is loaded or "
                   "saved, for RTT's maps and under mpirun)"
                 : std::string()) +
            " (default: " + default_render_tracer() + ")");
    CLI::Option* threads =
        cmd->add_option("--threads", job->threads,
                        "Worker threads (default: all cores; results do not depend on it. `rtt "
                        "bench` defaults to 1 to time one core)");
    cmd->add_option("--max-depth", job->max_depth, "Mirror reflection depth (0 = no reflections)")
        ->capture_default_str();
    cmd->add_option(
        "-o,--output", job->image,
        "Image file, format by extension: .png (8-bit sRGB), .exr (linear float RGB and "
        "--aov layers), .pfm (linear float), .ppm. Without any output option: <scene>.png");
    cmd->add_option(
           "--aov", job->aovs,
           "Extra EXR layers (comma-separated): depth (t of each pixel's first sample), normal "
           "(its triangle's unit normal), triangle (its id), rtt (share of samples RTT answered)")
        ->delimiter(',');
    cmd->add_option("--hits", job->hits, "Write the RTTH hit buffer (closest triangle per sample)");
    cmd->add_option("--shadows", job->shadows,
                    "Write the RTTS shadow buffer (visible lights per sample)");
    cmd->add_flag("--stats", job->stats,
                  "Print rays, time and Mrays/s per kind (primary, shadow, secondary)");
    cmd->add_option("--stats-json", job->stats_json, "Write the statistics as JSON");
    cmd->add_flag("-q,--quiet", job->quiet, "No progress bar");
    cmd->add_option("--rank-timeout", job->rank_timeout,
                    "Under mpirun: seconds a rank may hold a band (at least; 10x the slowest band "
                    "so far) before rank 0 stops the job as hung")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
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
        if (job->list_cameras) return list_cameras(*job);
        // No silent no-op: a render that asks for nothing writes the image and says where.
        const bool defaulted = has_no_output(*job);
        if (defaulted) {
            job->image = default_image_path(job->scene);
            if (!job->camera_path.empty())
                job->image.insert(job->image.size() - 4, "_%04d");  // before ".png"
        }
        run_render_job(*job);
        if (defaulted && mpi_rank() == 0)
            std::printf("rtt: wrote %s (choose outputs with -o, --hits, --shadows, --stats)\n",
                        job->image.c_str());
    });
}

}  // namespace rtt::cli
