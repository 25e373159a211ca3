#include "mpi_render.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <mutex>
#include <thread>

#include "render/progress.h"
#include "result_bytes.h"
#include "rtt/error.h"

#ifdef RTT_HAVE_MPI
#include <mpi.h>
#endif

namespace rtt::cli {

#ifndef RTT_HAVE_MPI

void mpi_start(int&, char**&) {}
void mpi_finish() {}
bool mpi_distributed() {
    return false;
}
int mpi_rank() {
    return 0;
}
int mpi_size() {
    return 1;
}
void mpi_abort(const std::string& message) {
    std::fprintf(stderr, "rtt: error: %s\n", message.c_str());
    std::exit(1);
}
RenderResult render_distributed(const Scene& scene, const Tracer& tracer,
                                const RenderOptions& options, const AnswerMaps& maps,
                                std::vector<RankStats>*, double) {
    return render(scene, tracer, options, maps);
}
KdTree share_tree(const Scene&, const std::function<KdTree()>& build, double) {
    return build();
}
void distribute_items(size_t count, const std::function<std::vector<char>(size_t)>& work,
                      const std::function<void(size_t, std::vector<char>&)>& done,
                      std::vector<RankStats>*, double, uint64_t) {
    for (size_t i = 0; i < count; ++i) {
        std::vector<char> bytes = work(i);
        done(i, bytes);
    }
}

#else

namespace {

bool started = false;
int world_rank = 0, world_size = 1;

enum Tag : int { request = 1, band = 2, result_header = 3, result_data = 4 };

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

/// Sums the ray statistics of every rank on rank 0 (counts are sums over tiles, so they equal
/// a one-process run's).
void reduce_stats(RenderStats& s) {
    KindStats* kinds[3] = {&s.primary, &s.shadow, &s.secondary};
    std::vector<uint64_t> counts;
    std::vector<double> seconds;
    for (KindStats* k : kinds) {
        const auto counters = k->counter_values();
        counts.insert(counts.end(), counters.begin(), counters.end());
        seconds.push_back(k->seconds);
    }
    counts.insert(counts.end(), s.rays_by_depth.begin(), s.rays_by_depth.end());
    std::vector<uint64_t> counts_sum(counts.size());
    std::vector<double> seconds_sum(seconds.size());
    MPI_Reduce(counts.data(), counts_sum.data(), int(counts.size()), MPI_UINT64_T, MPI_SUM, 0,
               MPI_COMM_WORLD);
    MPI_Reduce(seconds.data(), seconds_sum.data(), int(seconds.size()), MPI_DOUBLE, MPI_SUM, 0,
               MPI_COMM_WORLD);
    if (world_rank != 0) return;
    size_t i = 0;
    for (int k = 0; k < 3; ++k) {
        for (uint64_t* field : kinds[k]->counters()) *field = counts_sum[i++];
        kinds[k]->seconds = seconds_sum[size_t(k)];
    }
    for (uint64_t& d : s.rays_by_depth) d = counts_sum[i++];
}

/// Rank 0's watch over the other ranks (docs/distributed.md, "Faults"): a rank that holds work,
/// or leaves rank 0 waiting once rank 0 has nothing left, for longer than max(timeout, 10x the
/// slowest piece of work so far) ends the job, named.
class Watchdog {
public:
    explicit Watchdog(double timeout)
        : timeout_(timeout),
          held_(size_t(world_size)),
          since_(size_t(world_size), Clock::now()),
          done_(size_t(world_size), false) {}

    /// Rank r got work described by `what` ("pixel rows 384..", "frame 3"); empty = no more.
    void handed(int r, std::string what) {
        held_[size_t(r)] = std::move(what);
        done_[size_t(r)] = held_[size_t(r)].empty();
        since_[size_t(r)] = Clock::now();
    }
    /// Rank r returned its work.
    void returned(int r) {
        slowest_ = std::max(slowest_, seconds_since(since_[size_t(r)]));
        held_[size_t(r)].clear();
        since_[size_t(r)] = Clock::now();
    }
    /// Checks every rank; `rank0_idle`: rank 0 has rendered all it will.
    void check(bool rank0_idle) {
        const double limit = std::max(timeout_, 10 * slowest_);
        if (rank0_idle && idle_since_ == Clock::time_point{}) idle_since_ = Clock::now();
        for (int r = 1; r < world_size; ++r) {
            if (done_[size_t(r)]) continue;
            const std::string who = "rank " + std::to_string(r);
            if (!held_[size_t(r)].empty() && seconds_since(since_[size_t(r)]) > limit)
                mpi_abort(who + " has not returned " + held_[size_t(r)] + " after " +
                          std::to_string(int(seconds_since(since_[size_t(r)]))) +
                          " s (hung or far slower than the others; --rank-timeout)");
            if (held_[size_t(r)].empty() && idle_since_ != Clock::time_point{} &&
                seconds_since(std::max(since_[size_t(r)], idle_since_)) > limit)
                mpi_abort(who + " has not asked for work for " + std::to_string(int(limit)) +
                          " s while rank 0 waits to finish (hung while loading or building?; "
                          "--rank-timeout)");
        }
    }

private:
    double timeout_;
    double slowest_ = 0;
    std::vector<std::string> held_;
    std::vector<Clock::time_point> since_;
    std::vector<bool> done_;
    Clock::time_point idle_since_{};
};

/// Rank 0's dispatcher loop (the only thread of rank 0 that calls MPI while it renders): hands
/// out work on request with give(item), which describes it ("frame 3"; "" when none is left),
/// passes results to receive(header, bytes), until every other rank was told there is no more.
/// Polls and sleeps rather than blocks: Open MPI's blocking receive spins, and a spinning
/// dispatcher would take a core from rank 0's render threads.
using Give = std::function<std::string(int (&item)[2])>;
using Receive = std::function<void(const int (&header)[2], std::vector<char>& bytes)>;

void dispatch(Watchdog& watchdog, const std::atomic<bool>& rank0_idle, const Give& give,
              const Receive& receive) {
    int finished = 0;
    std::vector<char> bytes;
    while (finished < world_size - 1) {
        int waiting = 0;
        MPI_Status status;
        MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &waiting, &status);
        if (!waiting) {
            std::this_thread::sleep_for(std::chrono::microseconds(200));
            watchdog.check(rank0_idle);
            continue;
        }
        int header[2];
        MPI_Recv(header, 2, MPI_INT, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD, &status);
        const int from = status.MPI_SOURCE;
        if (status.MPI_TAG == request) {
            int item[2] = {-1, 0};
            std::string what = give(item);
            if (what.empty()) item[0] = -1, ++finished;
            watchdog.handed(from, std::move(what));
            MPI_Send(item, 2, MPI_INT, from, band, MPI_COMM_WORLD);
        } else if (status.MPI_TAG == result_header) {
            int size = 0;
            MPI_Status data_status;
            MPI_Probe(from, result_data, MPI_COMM_WORLD, &data_status);
            MPI_Get_count(&data_status, MPI_BYTE, &size);
            bytes.resize(size_t(size));
            MPI_Recv(bytes.data(), size, MPI_BYTE, from, result_data, MPI_COMM_WORLD,
                     MPI_STATUS_IGNORE);
            watchdog.returned(from);
            receive(header, bytes);
        }
    }
}

/// Rank 0: does its own share with own_work() while a dispatcher thread serves the other ranks
/// and watches them. An error in its own share ends the job (the dispatcher cannot be left).
void serve_while(double timeout_seconds, const Give& give, const Receive& receive,
                 const std::function<void()>& own_work) {
    Watchdog watchdog(timeout_seconds);
    std::atomic<bool> own_done{false};
    std::thread dispatcher([&] { dispatch(watchdog, own_done, give, receive); });
    try {
        own_work();
    } catch (const std::exception& e) {
        mpi_abort(e.what());
    }
    own_done = true;
    dispatcher.join();
}

/// A worker's side: asks rank 0 for an item; false when there is none left.
bool ask(int (&item)[2]) {
    int h[2] = {0, 0};
    MPI_Send(h, 2, MPI_INT, 0, request, MPI_COMM_WORLD);
    MPI_Recv(item, 2, MPI_INT, 0, band, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    return item[0] >= 0;
}

/// A worker's side: sends a result with its header.
void send_result(const int (&header)[2], const std::vector<char>& bytes) {
    MPI_Send(header, 2, MPI_INT, 0, result_header, MPI_COMM_WORLD);
    MPI_Send(bytes.data(), int(bytes.size()), MPI_BYTE, 0, result_data, MPI_COMM_WORLD);
}

/// Gathers every rank's RankStats on rank 0.
void gather_rank_stats(const RankStats& mine, std::vector<RankStats>* ranks) {
    std::vector<double> rank_values(size_t(world_size) * 3);
    const double values[3] = {double(mine.tiles), mine.busy_seconds, mine.idle_seconds};
    MPI_Gather(values, 3, MPI_DOUBLE, rank_values.data(), 3, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    if (world_rank != 0 || !ranks) return;
    ranks->clear();
    for (int r = 0; r < world_size; ++r)
        ranks->push_back({r, uint64_t(rank_values[size_t(r) * 3]), rank_values[size_t(r) * 3 + 1],
                          rank_values[size_t(r) * 3 + 2]});
}

}  // namespace

void mpi_start(int& argc, char**& argv) {
    // Only under a launcher: a plain `rtt` must not need an MPI runtime to start.
    if (!std::getenv("OMPI_COMM_WORLD_SIZE") && !std::getenv("PMI_SIZE") &&
        !std::getenv("PMIX_RANK"))
        return;
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_SERIALIZED, &provided);
    started = true;
    MPI_Comm_rank(MPI_COMM_WORLD, &world_rank);
    MPI_Comm_size(MPI_COMM_WORLD, &world_size);
    if (world_size > 1 && provided < MPI_THREAD_SERIALIZED)
        mpi_abort(
            "this MPI library cannot be called from a dispatcher thread (MPI_THREAD_SERIALIZED)");
}

void mpi_finish() {
    if (started) MPI_Finalize();
    started = false;
}

bool mpi_distributed() {
    return world_size > 1;
}
int mpi_rank() {
    return world_rank;
}
int mpi_size() {
    return world_size;
}

void mpi_abort(const std::string& message) {
    std::fprintf(stderr, "rtt: error: rank %d of %d: %s\n", world_rank, world_size,
                 message.c_str());
    std::fflush(stderr);
    if (started) MPI_Abort(MPI_COMM_WORLD, 1);
    std::exit(1);
}

namespace {

/// Waits for a non-blocking operation with short sleeps: Open MPI's blocking calls spin, and a
/// rank waiting for rank 0's build would take a core from it on a shared host.
/// Rank 0 gives up after timeout_seconds (a rank that hangs before taking the tree); the other
/// ranks wait as long as rank 0's build takes.
void wait_quietly(MPI_Request& request, double timeout_seconds) {
    const auto start = Clock::now();
    for (int done = 0;;) {
        MPI_Test(&request, &done, MPI_STATUS_IGNORE);
        if (done) return;
        if (world_rank == 0 && seconds_since(start) > timeout_seconds)
            mpi_abort("a rank has not taken the kd-tree after " +
                      std::to_string(int(timeout_seconds)) +
                      " s (hung while loading?; --rank-timeout)");
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
}

}  // namespace

KdTree share_tree(const Scene& scene, const std::function<KdTree()>& build,
                  double timeout_seconds) {
    if (world_size < 2) return build();
    KdTree tree;
    std::vector<char> bytes;
    uint64_t header[2] = {0, geometry_hash(scene)};  // tree bytes, rank 0's geometry hash
    if (world_rank == 0) {
        tree = build();
        bytes = pack_tree(tree);
        header[0] = bytes.size();
    }
    const uint64_t mine = header[1];
    MPI_Request request;
    MPI_Ibcast(header, 2, MPI_UINT64_T, 0, MPI_COMM_WORLD, &request);
    wait_quietly(request, timeout_seconds);
    if (header[1] != mine)
        mpi_abort(
            "this rank's scene is not rank 0's (the geometry differs; every rank must load "
            "the same file)");
    bytes.resize(header[0]);
    // MPI counts are ints: the tree goes in pieces of at most 1 GiB.
    for (uint64_t offset = 0; offset < header[0]; offset += uint64_t(1) << 30) {
        const int count = int(std::min<uint64_t>(header[0] - offset, uint64_t(1) << 30));
        MPI_Ibcast(bytes.data() + offset, count, MPI_BYTE, 0, MPI_COMM_WORLD, &request);
        wait_quietly(request, timeout_seconds);
    }
    return world_rank == 0 ? tree : unpack_tree(bytes);
}

RenderResult render_distributed(const Scene& scene, const Tracer& tracer,
                                const RenderOptions& options, const AnswerMaps& maps,
                                std::vector<RankStats>* ranks, double timeout_seconds) {
    options.validate(scene.lights.size());
    maps.validate(options, scene.lights.size());
    const int tiles_x = (options.width + 3) / 4, tiles_y = (options.height + 3) / 4;
    // About 8 bands per rank: small enough to balance, large enough that a band's tiles keep a
    // rank's threads busy. Bands start on the regions' grid, so every region is the one render()
    // traces: which rays RTT answers (the maps, the counts) depends on where regions are cut.
    const int region_tiles = options.region_pixels() / 4;
    const int band_rows = std::max(1, tiles_y / (8 * world_size * region_tiles)) * region_tiles;
    RankStats mine{world_rank, 0, 0, 0};
    const auto start = Clock::now();
    RenderResult whole;
    RenderStats stats;
    RenderOptions local = options;
    local.progress = false;  // rank 0's bar below counts every rank's bands

    if (world_rank == 0) {
        allocate_whole(whole, options, maps);
        render_detail::ProgressBar progress(uint64_t(tiles_y), options.progress);
        std::atomic<int> next_row{0};
        const auto take_band = [&](int& first, int& count) {
            first = next_row.fetch_add(band_rows);
            if (first >= tiles_y) return false;
            count = std::min(band_rows, tiles_y - first);
            return true;
        };
        serve_while(
            timeout_seconds,
            [&](int(&item)[2]) {
                return take_band(item[0], item[1])
                           ? "pixel rows " + std::to_string(4 * item[0]) + ".."
                           : std::string();
            },
            [&](const int(&header)[2], std::vector<char>& bytes) {
                unpack(bytes.data(), whole, header[0], BandLayout(options, header[1]));
                progress.advance(uint64_t(header[1] + 3) / 4);
            },
            [&] {
                const auto busy_start = Clock::now();
                stats = render_bands(
                    scene, tracer, local, take_band,
                    [&](RenderResult& band) {
                        // Rank 0's own bands go straight into the image (other rows than the
                        // dispatcher's).
                        unpack(pack(band).data(), whole, band.first_row,
                               BandLayout(options, band.rows));
                        progress.advance(uint64_t(band.rows + 3) / 4);
                        mine.tiles += uint64_t(band.rows + 3) / 4 * uint64_t(tiles_x);
                    },
                    maps);
                mine.busy_seconds = seconds_since(busy_start);
            });
    } else {
        double busy = 0;
        auto band_start = Clock::now();
        stats = render_bands(
            scene, tracer, local,
            [&](int& first, int& count) {
                int item[2];
                const bool more = ask(item);
                first = item[0], count = item[1];
                band_start = Clock::now();
                return more;
            },
            [&](RenderResult& band) {
                busy += seconds_since(band_start);
                mine.tiles += uint64_t((band.rows + 3) / 4) * uint64_t(tiles_x);
                send_result({band.first_row, band.rows}, pack(band));
            },
            maps);
        mine.busy_seconds = busy;
    }
    mine.idle_seconds = std::max(0.0, seconds_since(start) - mine.busy_seconds);
    reduce_stats(stats);
    gather_rank_stats(mine, ranks);
    if (world_rank != 0) return RenderResult{};
    stats.wall_seconds = seconds_since(start);
    whole.stats = stats;
    return whole;
}

void distribute_items(size_t count, const std::function<std::vector<char>(size_t)>& work,
                      const std::function<void(size_t, std::vector<char>&)>& done,
                      std::vector<RankStats>* ranks, double timeout_seconds,
                      uint64_t tiles_per_item) {
    RankStats mine{world_rank, 0, 0, 0};
    const auto start = Clock::now();
    const auto run = [&](size_t item) {
        const auto item_start = Clock::now();
        std::vector<char> bytes = work(item);
        mine.busy_seconds += seconds_since(item_start);
        mine.tiles += tiles_per_item;
        return bytes;
    };
    if (world_rank == 0) {
        std::atomic<size_t> next{0};
        std::mutex done_mutex;  // done() runs on both of rank 0's threads, one at a time
        const auto finish = [&](size_t item, std::vector<char>& bytes) {
            const std::lock_guard<std::mutex> lock(done_mutex);
            try {
                done(item, bytes);
            } catch (const std::exception& e) {
                mpi_abort(e.what());
            }
        };
        serve_while(
            timeout_seconds,
            [&](int(&item)[2]) {
                const size_t i = next.fetch_add(1);
                item[0] = i < count ? int(i) : -1;
                return i < count ? "item " + std::to_string(i) : std::string();
            },
            [&](const int(&header)[2], std::vector<char>& bytes) {
                finish(size_t(header[0]), bytes);
            },
            [&] {
                for (size_t i; (i = next.fetch_add(1)) < count;) {
                    std::vector<char> bytes = run(i);
                    finish(i, bytes);
                }
            });
    } else {
        for (int item[2]; ask(item);) send_result({item[0], 0}, run(size_t(item[0])));
    }
    mine.idle_seconds = std::max(0.0, seconds_since(start) - mine.busy_seconds);
    gather_rank_stats(mine, ranks);
}

#endif

void render_frames_distributed(size_t frames, const RenderOptions& options, const AnswerMaps& maps,
                               const std::function<RenderResult(size_t)>& render_frame,
                               const std::function<void(size_t, RenderResult&)>& frame_done,
                               std::vector<RankStats>* ranks, double timeout_seconds) {
    const uint64_t tiles = uint64_t((options.width + 3) / 4) * uint64_t((options.height + 3) / 4);
    // A frame travels as its packed arrays followed by its packed ray statistics.
    const auto stats_bytes = [&] {
        RenderStats empty;
        empty.rays_by_depth.assign(size_t(options.max_depth) + 1, 0);
        return pack_stats(empty).size();
    }();
    distribute_items(
        frames,
        [&](size_t f) {
            const RenderResult r = render_frame(f);
            std::vector<char> bytes = pack(r);
            const std::vector<char> stats = pack_stats(r.stats);
            bytes.insert(bytes.end(), stats.begin(), stats.end());
            return bytes;
        },
        [&](size_t f, std::vector<char>& bytes) {
            RenderResult r;
            allocate_whole(r, options, maps);
            r.stats.rays_by_depth.assign(size_t(options.max_depth) + 1, 0);
            unpack(bytes.data(), r, 0, BandLayout(options, options.height));
            unpack_stats(bytes.data() + bytes.size() - stats_bytes, r.stats);
            frame_done(f, r);
        },
        ranks, timeout_seconds, tiles);
}

}  // namespace rtt::cli
