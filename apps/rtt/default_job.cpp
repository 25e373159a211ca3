// `rtt` with no arguments: the README's main job.
#include <cstdio>

#include "commands.h"
#include "experiments/experiments.h"
#include "render_job.h"
#include "stats_report.h"

namespace rtt::cli {

void run_default_job() {
    RenderJob job;
    job.scene.scene = "room";
    job.size = "640x480";
    job.image = "room.png";
    job.tracer = default_tracer_kind();  // RTT itself, as the table after the image
    std::printf("rtt: rendering the built-in scene 'room' at 640x480 (tracer %s) -> room.png\n",
                job.tracer.c_str());
    std::fflush(stdout);
    const RenderJobResult r = run_render_job(job);
    print_stats(stdout, r);
    bench::print_rtt_vs_packet(stdout, "room");
}

}  // namespace rtt::cli
