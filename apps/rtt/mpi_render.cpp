#include "mpi_render.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <thread>

#include "render/progress.h"
#include "rtt/error.h"

#ifdef RTT_HAVE_MPI
#include <mpi.h>
#endif

namespace rtt::cli {

#ifndef RTT_HAVE_MPI

void mpi_start(int&, char**&) {}
void mpi_finish() {}
bool mpi_distributed() { return false; }
int mpi_rank() { return 0; }
int mpi_size() { return 1; }
void mpi_abort(const std::string& message) {
    std::fprintf(stderr, "rtt: error: %s\n", message.c_str());
    std::exit(1);
}
RenderResult render_distributed(const Scene& scene, const Tracer& tracer, const RenderOptions& options,
                                std::vector<RankStats>*, double) {
    return render(scene, tracer, options);
}

#else

namespace {

bool started = false;
int world_rank = 0, world_size = 1;

enum Tag : int { request = 1, band = 2, result_header = 3, result_data = 4 };

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// The per-pixel and per-sample arrays of a band, in one fixed order: what travels between
/// ranks. Sizes follow from the options and the band's rows, so only the bytes are sent.
struct BandLayout {
    size_t pixels, samples;
    BandLayout(const RenderOptions& o, int rows)
        : pixels(size_t(o.width) * size_t(rows)), samples(pixels * size_t(o.aa) * size_t(o.aa)) {}
};

template <typename T>
void append(std::vector<char>& bytes, const std::vector<T>& v) {
    const char* p = reinterpret_cast<const char*>(v.data());
    bytes.insert(bytes.end(), p, p + v.size() * sizeof(T));
}

template <typename T>
void take(const char*& p, std::vector<T>& into, size_t offset, size_t count) {
    if (into.empty()) return;  // this array is not asked for
    std::memcpy(into.data() + offset, p, count * sizeof(T));
    p += count * sizeof(T);
}

std::vector<char> pack(const RenderResult& b) {
    std::vector<char> bytes;
    append(bytes, b.pixels);
    append(bytes, b.hits);
    append(bytes, b.shadows);
    append(bytes, b.primary_map);
    append(bytes, b.shadow_map);
    append(bytes, b.depth);
    append(bytes, b.first_triangle);
    return bytes;
}

/// Copies a packed band into the whole image's arrays (allocated as render() would).
void unpack(const char* p, RenderResult& whole, int first_row, const BandLayout& band) {
    const size_t px = size_t(first_row) * size_t(whole.width), spp = size_t(whole.aa) * size_t(whole.aa);
    take(p, whole.pixels, px, band.pixels);
    take(p, whole.hits, px * spp, band.samples);
    take(p, whole.shadows, px * spp, band.samples);
    take(p, whole.primary_map, px, band.pixels);
    take(p, whole.shadow_map, px, band.pixels);
    take(p, whole.depth, px, band.pixels);
    take(p, whole.first_triangle, px, band.pixels);
}

void allocate_whole(RenderResult& out, const RenderOptions& o) {
    const size_t pixels = size_t(o.width) * size_t(o.height), samples = pixels * size_t(o.aa) * size_t(o.aa);
    out.width = o.width, out.height = o.height, out.aa = o.aa, out.first_row = 0, out.rows = o.height;
    out.pixels.resize(pixels);
    if (o.hits_buffer) out.hits.resize(samples);
    if (o.shadow_buffer) out.shadows.resize(samples);
    if (o.primary_map) out.primary_map.resize(pixels);
    if (o.shadow_map_light >= 0) out.shadow_map.resize(pixels);
    if (o.pixel_hits) out.depth.resize(pixels), out.first_triangle.resize(pixels);
}

/// Sums the ray statistics of every rank on rank 0 (counts are sums over tiles, so they equal
/// a one-process run's).
void reduce_stats(RenderStats& s) {
    KindStats* kinds[3] = {&s.primary, &s.shadow, &s.secondary};
    std::vector<uint64_t> counts;
    std::vector<double> seconds;
    for (KindStats* k : kinds) {
        const TraceStats& t = k->trace;
        counts.insert(counts.end(), {t.tiles, t.rtt_tiles, t.rays, t.traced, t.answered, t.relevant_sum});
        seconds.push_back(k->seconds);
    }
    counts.insert(counts.end(), s.rays_by_depth.begin(), s.rays_by_depth.end());
    std::vector<uint64_t> counts_sum(counts.size());
    std::vector<double> seconds_sum(seconds.size());
    MPI_Reduce(counts.data(), counts_sum.data(), int(counts.size()), MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
    MPI_Reduce(seconds.data(), seconds_sum.data(), int(seconds.size()), MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
    if (world_rank != 0) return;
    size_t i = 0;
    for (int k = 0; k < 3; ++k) {
        TraceStats& t = kinds[k]->trace;
        for (uint64_t* field : {&t.tiles, &t.rtt_tiles, &t.rays, &t.traced, &t.answered, &t.relevant_sum})
            *field = counts_sum[i++];
        kinds[k]->seconds = seconds_sum[size_t(k)];
    }
    for (uint64_t& d : s.rays_by_depth) d = counts_sum[i++];
}

}  // namespace

void mpi_start(int& argc, char**& argv) {
    // Only under a launcher: a plain `rtt` must not need an MPI runtime to start.
    if (!std::getenv("OMPI_COMM_WORLD_SIZE") && !std::getenv("PMI_SIZE") && !std::getenv("PMIX_RANK")) return;
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_SERIALIZED, &provided);
    started = true;
    MPI_Comm_rank(MPI_COMM_WORLD, &world_rank);
    MPI_Comm_size(MPI_COMM_WORLD, &world_size);
    if (world_size > 1 && provided < MPI_THREAD_SERIALIZED)
        mpi_abort("this MPI library cannot be called from a dispatcher thread (MPI_THREAD_SERIALIZED)");
}

void mpi_finish() {
    if (started) MPI_Finalize();
    started = false;
}

bool mpi_distributed() { return world_size > 1; }
int mpi_rank() { return world_rank; }
int mpi_size() { return world_size; }

void mpi_abort(const std::string& message) {
    std::fprintf(stderr, "rtt: error: rank %d of %d: %s\n", world_rank, world_size, message.c_str());
    std::fflush(stderr);
    if (started) MPI_Abort(MPI_COMM_WORLD, 1);
    std::exit(1);
}

RenderResult render_distributed(const Scene& scene, const Tracer& tracer, const RenderOptions& options,
                                std::vector<RankStats>* ranks, double timeout_seconds) {
    options.validate(scene.lights.size());
    const int tiles_x = (options.width + 3) / 4, tiles_y = (options.height + 3) / 4;
    // About 8 bands per rank: small enough to balance, large enough that a band's tiles keep a
    // rank's threads busy.
    const int band_rows = std::max(1, tiles_y / (8 * world_size));
    RankStats mine{world_rank, 0, 0, 0};
    const auto start = Clock::now();
    RenderResult whole;
    RenderStats stats;
    RenderOptions local = options;
    local.progress = false;  // rank 0's bar below counts every rank's bands

    if (world_rank == 0) {
        allocate_whole(whole, options);
        render_detail::ProgressBar progress(uint64_t(tiles_y), options.progress);
        std::atomic<int> next_row{0};
        const auto take_band = [&](int& first, int& count) {
            first = next_row.fetch_add(band_rows);
            if (first >= tiles_y) return false;
            count = std::min(band_rows, tiles_y - first);
            return true;
        };
        // The dispatcher: the only thread of rank 0 that calls MPI while the render runs. It
        // also watches the other ranks: one that holds a band, or leaves rank 0 waiting at the
        // end, for longer than the timeout stops the job (docs/distributed.md, "Faults").
        std::atomic<bool> own_done{false};
        std::thread dispatcher([&] {
            int finished = 0;
            std::vector<char> bytes;
            std::vector<int> held(size_t(world_size), -1);  // first row of a rank's band, -1 none
            std::vector<Clock::time_point> since(size_t(world_size), start);
            std::vector<bool> done(size_t(world_size), false);
            double slowest_band = 0;
            Clock::time_point own_done_at{};
            while (finished < world_size - 1) {
                // Poll and sleep rather than block: Open MPI's blocking receive spins, and the
                // spinning dispatcher would take a core from rank 0's render threads.
                int waiting = 0;
                MPI_Status status;
                MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &waiting, &status);
                if (!waiting) {
                    std::this_thread::sleep_for(std::chrono::microseconds(200));
                    // A band may take up to 10x the slowest one so far, and never less than the
                    // timeout; a rank with no band is waited for once rank 0 has nothing left.
                    const double limit = std::max(timeout_seconds, 10 * slowest_band);
                    if (own_done && own_done_at == Clock::time_point{}) own_done_at = Clock::now();
                    for (int r = 1; r < world_size; ++r) {
                        if (done[size_t(r)]) continue;
                        if (held[size_t(r)] >= 0 && seconds_since(since[size_t(r)]) > limit)
                            mpi_abort("rank " + std::to_string(r) + " has not returned pixel rows " +
                                      std::to_string(4 * held[size_t(r)]) + ".. after " +
                                      std::to_string(int(seconds_since(since[size_t(r)]))) +
                                      " s (hung or far slower than the others; --rank-timeout)");
                        if (held[size_t(r)] < 0 && own_done_at != Clock::time_point{} &&
                            seconds_since(std::max(since[size_t(r)], own_done_at)) > limit)
                            mpi_abort("rank " + std::to_string(r) + " has not asked for work for " +
                                      std::to_string(int(limit)) +
                                      " s while rank 0 waits to finish (hung while loading or "
                                      "building?; --rank-timeout)");
                    }
                    continue;
                }
                int header[2];
                MPI_Recv(header, 2, MPI_INT, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD, &status);
                const int from = status.MPI_SOURCE;
                if (status.MPI_TAG == request) {
                    int b[2] = {-1, 0};
                    if (!take_band(b[0], b[1])) b[0] = -1, ++finished, done[size_t(from)] = true;
                    MPI_Send(b, 2, MPI_INT, from, band, MPI_COMM_WORLD);
                    held[size_t(from)] = b[0];
                } else if (status.MPI_TAG == result_header) {
                    const int first_row = header[0], rows = header[1];
                    int size = 0;
                    MPI_Status data_status;
                    MPI_Probe(from, result_data, MPI_COMM_WORLD, &data_status);
                    MPI_Get_count(&data_status, MPI_BYTE, &size);
                    bytes.resize(size_t(size));
                    MPI_Recv(bytes.data(), size, MPI_BYTE, from, result_data, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
                    unpack(bytes.data(), whole, first_row, BandLayout(options, rows));
                    progress.advance(uint64_t(rows + 3) / 4);
                    slowest_band = std::max(slowest_band, seconds_since(since[size_t(from)]));
                    held[size_t(from)] = -1;
                }
                since[size_t(from)] = Clock::now();
            }
        });
        auto busy_start = Clock::now();
        stats = render_bands(scene, tracer, local, take_band, [&](RenderResult& band) {
            // Rank 0's own bands go straight into the image (other rows than the dispatcher's).
            unpack(pack(band).data(), whole, band.first_row, BandLayout(options, band.rows));
            progress.advance(uint64_t(band.rows + 3) / 4);
            mine.tiles += uint64_t(band.rows + 3) / 4 * uint64_t(tiles_x);
        });
        mine.busy_seconds = seconds_since(busy_start);
        own_done = true;
        dispatcher.join();
    } else {
        double busy = 0;
        const auto ask = [&](int& first, int& count) {
            int h[2] = {0, 0}, b[2];
            MPI_Send(h, 2, MPI_INT, 0, request, MPI_COMM_WORLD);
            MPI_Recv(b, 2, MPI_INT, 0, band, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            first = b[0], count = b[1];
            return first >= 0;
        };
        auto band_start = Clock::now();
        stats = render_bands(scene, tracer, local, [&](int& first, int& count) {
            const bool more = ask(first, count);
            band_start = Clock::now();
            return more;
        }, [&](RenderResult& band) {
            busy += seconds_since(band_start);
            mine.tiles += uint64_t((band.rows + 3) / 4) * uint64_t(tiles_x);
            const std::vector<char> bytes = pack(band);
            int h[2] = {band.first_row, band.rows};
            MPI_Send(h, 2, MPI_INT, 0, result_header, MPI_COMM_WORLD);
            MPI_Send(bytes.data(), int(bytes.size()), MPI_BYTE, 0, result_data, MPI_COMM_WORLD);
        });
        mine.busy_seconds = busy;
    }
    mine.idle_seconds = std::max(0.0, seconds_since(start) - mine.busy_seconds);
    reduce_stats(stats);
    std::vector<double> rank_values(size_t(world_size) * 3);
    const double values[3] = {double(mine.tiles), mine.busy_seconds, mine.idle_seconds};
    MPI_Gather(values, 3, MPI_DOUBLE, rank_values.data(), 3, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    if (world_rank != 0) return RenderResult{};
    if (ranks) {
        ranks->clear();
        for (int r = 0; r < world_size; ++r)
            ranks->push_back({r, uint64_t(rank_values[size_t(r) * 3]), rank_values[size_t(r) * 3 + 1],
                              rank_values[size_t(r) * 3 + 2]});
    }
    stats.wall_seconds = seconds_since(start);
    whole.stats = stats;
    return whole;
}

#endif

}  // namespace rtt::cli
