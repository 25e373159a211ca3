// Rendering across machines with MPI (README, "Distributed rendering"): started by mpirun with
// several ranks, every rank loads the scene and builds its tree; rank 0 hands out bands of tile
// rows (or, for camera paths, whole frames) on demand (a dispatcher thread answers requests while
// rank 0 renders bands too), the other ranks render them with their own threads and send them back,
// and rank 0 assembles the image and buffers, bit for bit what one process renders, and writes
// every output. Without MPI in the build, or without mpirun, nothing here changes a run.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "rtt/kdtree.h"
#include "rtt/render.h"

namespace rtt::cli {

/// Starts MPI when the program was launched by mpirun (or another MPI launcher) and this build
/// has MPI; no-op otherwise. Call once at the start of main.
void mpi_start(int& argc, char**& argv);
/// Ends MPI if it was started.
void mpi_finish();

/// True when this run has more than one rank.
bool mpi_distributed();
/// This process's rank (0 without MPI), and the number of ranks (1 without MPI).
int mpi_rank();
int mpi_size();

/// Ends the whole job after a failure on this rank: prints "rtt: error: rank R: message" and
/// aborts every rank (the exit status is not 0, and rank 0 writes no output).
[[noreturn]] void mpi_abort(const std::string& message);

/// Default of --rank-timeout: seconds rank 0 waits for a rank's band (or, once rank 0 has
/// nothing left to render, for a rank to ask for work) before it stops the job.
inline constexpr double default_rank_timeout = 120;

/// The kd-tree every rank renders with: rank 0 builds it (build(), on all its threads) while the
/// other ranks wait without spinning, then sends it to them (faster than building it again on
/// every rank: docs/distributed.md). Each rank first checks that its scene's geometry is rank
/// 0's, or the job stops naming the rank. Without MPI, or with one rank: build().
KdTree share_tree(const Scene& scene, const std::function<KdTree()>& build,
                  double timeout_seconds = default_rank_timeout);

/// What one rank did in a distributed render: the load balance.
struct RankStats {
    int rank = 0;
    uint64_t tiles = 0;       ///< 4x4-pixel tiles it rendered.
    double busy_seconds = 0;  ///< Wall time rendering its bands.
    double idle_seconds = 0;  ///< Wall time waiting for bands or for the others to finish.
};

/// render() distributed over the ranks. Every rank must call it with the same scene, options and
/// maps.
/// Rank 0 gets the whole result, with the ray statistics summed over the ranks, and (if
/// `ranks`) every rank's RankStats; other ranks get an empty result. A rank silent for longer
/// than max(timeout_seconds, 10x the slowest band so far) ends the job (mpi_abort naming it).
RenderResult render_distributed(const Scene& scene, const Tracer& tracer,
                                const RenderOptions& options, const AnswerMaps& maps,
                                std::vector<RankStats>* ranks = nullptr,
                                double timeout_seconds = default_rank_timeout);

/// Items [0, count) spread over the ranks on demand: rank 0 hands out item numbers (a
/// dispatcher thread, as for bands), every rank (rank 0 too) runs work(i), which returns the
/// item's result as bytes, and rank 0 gets done(i, bytes) for each item in the order they
/// finish (never two at once; an exception there ends the job). Every rank must call it with
/// the same count. A rank silent past the timeout (as render_distributed) ends the job.
/// `ranks` (on rank 0): items x tiles_per_item, busy and idle seconds per rank. Without MPI:
/// the items in order.
void distribute_items(size_t count, const std::function<std::vector<char>(size_t)>& work,
                      const std::function<void(size_t, std::vector<char>&)>& done,
                      std::vector<RankStats>* ranks = nullptr,
                      double timeout_seconds = default_rank_timeout, uint64_t tiles_per_item = 0);

/// A sequence of frames distributed as whole frames (a camera path with at least as many frames
/// as ranks): rank 0 hands out frame numbers on demand, every rank (rank 0 too) renders a frame
/// with render_frame(f) on all its threads, and rank 0 calls frame_done(f, result) for each
/// frame in the order they finish (never two at once; an exception there ends the job). Every
/// rank must call it with the same arguments; `options` and `maps` give the arrays a frame holds.
/// `ranks` (on rank 0): frames' tiles, rendering and idle seconds per rank. Without MPI: the
/// frames in order.
void render_frames_distributed(size_t frames, const RenderOptions& options, const AnswerMaps& maps,
                               const std::function<RenderResult(size_t)>& render_frame,
                               const std::function<void(size_t, RenderResult&)>& frame_done,
                               std::vector<RankStats>* ranks = nullptr,
                               double timeout_seconds = default_rank_timeout);

}  // namespace rtt::cli
