// One `rtt render` run: the options as given on the command line, and the function that
// carries them out. The default main job and `rtt bench` reuse it.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "mpi_render.h"
#include "rtt/kdtree.h"
#include "rtt/render.h"
#include "scene_args.h"
#include "tree_args.h"

namespace rtt::cli {

struct RenderJob {
    SceneArgs scene;
    TreeArgs tree;  ///< --save-tree, --load-tree
    /// "px,py,pz,tx,ty,tz,ux,uy,uz,fovy", or N: the file's camera N (Scene::file_cameras);
    /// empty = the scene's or the default.
    std::string camera;
    bool list_cameras = false;     ///< --list-cameras: print the file's cameras, render nothing.
    std::string camera_path;       ///< --camera-path FILE: one camera per line, a frame each.
    std::string size = "640x480";  ///< "WxH".
    int aa = 1;
    int region = 0;  ///< --region: pixels per region side (0 = RenderOptions' default).
    std::vector<std::string> lights;  ///< "x,y,z" each; empty = scene's lights.
    std::string tracer;               ///< Empty = default_render_tracer().
    int threads = 0;                  ///< 0 = all cores.
    int max_depth = 4;
    std::string image;  ///< -o: .png (8-bit sRGB), .exr (linear float + AOVs), .pfm, .ppm.
    std::vector<std::string> aovs;  ///< --aov: depth, normal, triangle, rtt (EXR layers).
    bool wants_aov(const std::string& name) const {
        return std::find(aovs.begin(), aovs.end(), name) != aovs.end();
    }
    std::string hits;         ///< RTTH output.
    std::string shadows;      ///< RTTS output.
    std::string map_primary;  ///< Figure 5b PNG.
    std::string map_shadow;   ///< Figure 5c PNG.
    int map_light = 0;
    bool stats = false;
    std::string stats_json;
    bool quiet = false;
    double rank_timeout = default_rank_timeout;  ///< --rank-timeout (under mpirun).
};

/// What a job did, for callers that report more than the job itself prints.
struct RenderJobResult {
    std::string scene_label;
    size_t triangles = 0;
    size_t input_warnings = 0;    ///< Scene::warning_count of the loaded scene.
    std::string tracer;           ///< The kind that traced the last frame.
    bool tracer_auto = false;     ///< Chosen by `--tracer auto`.
    double kd_build_seconds = 0;  ///< Building, or loading with --load-tree (kd_loaded).
    bool kd_loaded = false;
    bool kd_used = true;  ///< False: the tracer needed no kd-tree (tracer_uses_kdtree).
    /// make_tracer: the tracer's own structures (the bvh kind's BVH, Embree's scene).
    double tracer_build_seconds = 0;
    KdStats kd_stats;
    RenderResult result;
    std::vector<RankStats> ranks;  ///< Under mpirun (on rank 0): what each rank did.
};

/// The extensions -o accepts, and the arbitrary output variables --aov accepts.
const std::vector<std::string>& image_extensions();
const std::vector<std::string>& aov_names();

/// True when the job asks for no output at all (no file, no statistics).
bool has_no_output(const RenderJob& job);

/// "<stem of the scene or mesh>.png" in the current folder: the image `rtt render` writes when
/// no output is asked for.
std::string default_image_path(const SceneArgs& scene);

/// "rtt" if this build has it, else "packet", else "ray".
std::string default_tracer_kind();

// `--tracer auto` (rtt::auto_tracer, auto_rays_per_triangle): run_render_job says how it picks.
/// True when this build has the kinds `auto` picks from (bvh and rtt).
bool has_auto_tracer();
/// `rtt render`'s default: auto where the build has it, else default_tracer_kind().
std::string default_render_tracer();

/// Loads the scene, applies --camera / --light, builds the kd-tree and tracer, renders and
/// writes every requested output, all of them or none (OutputSet). Throws rtt::Error on bad
/// input; everything that can be checked without rendering (options, output names, folders)
/// is checked before the scene is loaded.
RenderJobResult run_render_job(const RenderJob& job);

}  // namespace rtt::cli
