// `rtt view`: the interactive viewer's command line (apps/rtt/view/viewer.h does the work).
#include <memory>

#include "commands.h"
#include "mpi_render.h"
#include "render_job.h"
#include "rtt/error.h"
#include "rtt/tracer.h"
#include "view/view_state.h"
#include "view/viewer.h"

namespace rtt::cli {

void add_view_command(CLI::App& app) {
    auto o = std::make_shared<view::ViewerOptions>();
    CLI::App* cmd = app.add_subcommand(
        "view", "Interactive window: move the camera, switch tracers, watch what RTT answers");
    cmd->footer(std::string(view::key_help()) +
                "\nHeadless (tests, screenshots): xvfb-run rtt view --scene room --frames 3 "
                "--screenshot view.png\nrenders 3 frames in a window and saves the last; it "
                "equals `rtt render` with the same camera, size and K.");
    add_scene_options(*cmd, o->scene);
    cmd->add_option(
        "--camera", o->camera,
        "Starting camera px,py,pz,tx,ty,tz,ux,uy,uz,fovy (the C key prints the current one)");
    cmd->add_option("--light", o->lights, "Omni light at x,y,z (repeatable; replaces the scene's)");
    cmd->add_option("--size", o->size, "Window size WxH (frames are rendered pixel for pixel)")
        ->capture_default_str();
    cmd->add_option("--aa", o->aa, "Antialiasing K of a resting camera, 1..8 (moving: K = 1)")
        ->capture_default_str();
    std::string kinds;
    for (const std::string& k : tracer_kinds()) kinds += (kinds.empty() ? "" : ", ") + k;
    cmd->add_option("--tracer", o->tracer,
                    "First tracer shown (T cycles): " + kinds + ", or auto (default: " +
                        default_tracer_kind() + "; auto is the same: bvh shows the scene until " +
                        default_tracer_kind() + "'s kd-tree is built)");
    CLI::Option* threads =
        cmd->add_option("--threads", o->threads, "Worker threads (default: all cores)");
    cmd->add_option("--max-depth", o->max_depth, "Mirror reflection depth")->capture_default_str();
    cmd->add_flag("!--no-shadows", o->shadows, "Start with shadows off (L toggles)");
    cmd->add_option("--overlay", o->overlay,
                    "Start with an RTT map over the image: none, primary, shadow (M cycles)")
        ->capture_default_str();
    cmd->add_option("--frames", o->frames, "Render this many frames, then close (0 = until closed)")
        ->capture_default_str();
    cmd->add_option("--screenshot", o->screenshot,
                    "PNG of the window: after the last of --frames, and on the P key");
    cmd->add_flag("-q,--quiet", o->quiet, "No progress lines or key help");
    cmd->callback([o, threads] {
        if (threads->count() > 0 && o->threads < 1) throw Error("--threads must be at least 1");
        if (mpi_distributed()) throw Error("rtt view runs on one machine, not under mpirun");
        view::run_viewer(*o);
    });
}

}  // namespace rtt::cli
