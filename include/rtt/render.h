// The renderer: 4x4-pixel tiles, K x K antialiasing, Phong shading with omni and spot lights,
// shadow segments, mirrors, oneTBB threads. Rays go to a Tracer a tile at a time, as separate
// batches per kind (primary, shadow, secondary), so each kind is timed and counted on its own
// (the paper's Table 1 measures ray shooting only). What each batch holds, and why results do
// not depend on the thread count: docs/architecture.md, "What the renderer hands a tracer".
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "rtt/math.h"
#include "rtt/rtt_options.h"
#include "rtt/scene.h"
#include "rtt/tracer.h"

namespace rtt {

/// Largest image side accepted by render().
inline constexpr int max_image_side = 16384;
/// Largest antialiasing factor K (K x K samples per pixel).
inline constexpr int max_aa = 16;
/// Largest number of samples (W * H * K * K) per render: a hit or shadow buffer holds 4 bytes
/// per sample, so both together stay below 8 GiB. Checked before anything is allocated.
inline constexpr uint64_t max_render_samples = uint64_t(1) << 30;
/// Largest reflection depth accepted.
inline constexpr int max_reflection_depth = 64;
/// Largest thread count accepted (more is a typo, not a machine).
inline constexpr int max_render_threads = 1024;
/// Largest region side (pixels) accepted by RenderOptions::region.
inline constexpr int max_region = 256;
/// The default region side for K x K antialiasing: 32 pixels at K = 1, 8 pixels from K = 2 to 8
/// (16 to 64 samples a side), the 4x4-pixel tile above (docs/benchmarks.md, "Regions").
int default_region(int aa);

struct RenderOptions {
    Camera camera;
    int width = 640;
    int height = 480;
    int aa = 1;                  ///< K: K x K samples per pixel, 1..16.
    int max_depth = 4;           ///< Reflection bounces traced; 0 = no reflected rays.
    int threads = 0;             ///< Worker threads; 0 = all cores.
    bool hits_buffer = false;    ///< Fill RenderResult::hits.
    bool shadow_buffer = false;  ///< Fill RenderResult::shadows (every hit sample, every light).
    bool pixel_hits = false;     ///< Fill RenderResult::depth and first_triangle.
    /// Trace shadow segments. false: every light lights every point it faces (the viewer's
    /// shadows-off mode); no shadow buffer or shadow map then.
    bool shadows = true;
    bool progress = false;  ///< Progress bar on stderr (only when stderr is a terminal
                            ///< and the render takes longer than about a second).
    /// Side in pixels of the regions handed to the tracer as one tile (a multiple of 4, up to
    /// max_region; 0 = default_region(aa)). RTT tries a region as one shaft (at K = 1 a 4x4-pixel
    /// tile is a single 16-wide packet, too few rays to pay for a shaft); other tracers cut it
    /// into packets. Results do not depend on it, bit for bit.
    int region = 0;
    /// The region side render() uses: `region`, or default_region(aa) when it is 0.
    int region_pixels() const;

    /// Throws rtt::Error for a size, K, depth or thread count out of range, a shadow buffer
    /// without shadows, or a sample count above max_render_samples. `light_count` is the
    /// scene's number of lights.
    void validate(size_t light_count) const;
};

/// The paper's Figure 5: which samples RTT answered, per pixel. Measurement rather than image,
/// so asked for beside the options (render()'s optional argument), not among them.
struct AnswerMaps {
    bool primary = false;   ///< Fill RenderResult::primary_map (Figure 5b).
    int shadow_light = -1;  ///< >= 0: fill RenderResult::shadow_map for this light (Figure 5c).
    /// Throws rtt::Error for a light the scene does not have, or a shadow map without shadows.
    void validate(const RenderOptions& options, size_t light_count) const;
};

/// Counters and time of one kind of rays.
struct KindStats {
    TraceStats trace;
    RttStats rtt;        ///< Zero unless the tracer is an RTT one.
    double seconds = 0;  ///< Time inside tracer calls, summed over threads.
    /// The context that adds a tile's counters here (and its answers to `answers`).
    TraceContext context(std::span<SampleAnswer> answers = {}) {
        return TraceContext{&trace, &rtt, answers};
    }
    KindStats& operator+=(const KindStats& o) {
        trace += o.trace;
        rtt += o.rtt;
        seconds += o.seconds;
        return *this;
    }
    /// Every counter of both, for code that ships them all (bands, MPI ranks).
    std::vector<uint64_t*> counters() {
        std::vector<uint64_t*> all;
        for (uint64_t* c : trace.counters()) all.push_back(c);
        for (uint64_t* c : rtt.counters()) all.push_back(c);
        return all;
    }
    std::vector<uint64_t> counter_values() const {
        std::vector<uint64_t> all;
        for (uint64_t c : trace.counter_values()) all.push_back(c);
        for (uint64_t c : rtt.counter_values()) all.push_back(c);
        return all;
    }
    /// Rays asked for per second of tracer time, in millions (per-thread throughput).
    double mrays_per_second() const {
        return seconds > 0 ? double(trace.rays) / seconds * 1e-6 : 0.0;
    }
};

struct RenderStats {
    KindStats primary;
    KindStats shadow;     ///< Shadow segments of primary and of reflected hits.
    KindStats secondary;  ///< Reflected rays, all depths.
    /// Camera rays, shadow segments and reflected rays the tracer was given.
    uint64_t rays() const { return primary.trace.rays + shadow.trace.rays + secondary.trace.rays; }
    /// Reflected rays per depth: [0] = primary rays, [d] = rays of reflection depth d.
    std::vector<uint64_t> rays_by_depth;
    double wall_seconds = 0;  ///< Whole render, wall clock.
    int threads = 0;          ///< Threads used.
};

/// The soonest exact image, the default tracer of `rtt render` and rtt.render: frames come from
/// "bvh" until they have been given this many rays per triangle, then from "rtt" (the same hits
/// either way). The kd-tree and RTT's setup cost 1.1-1.4 us per triangle and `rtt` saves about
/// 5 ns per camera or shadow ray (docs/benchmarks.md, "First image").
inline constexpr const char* auto_tracer = "auto";
inline constexpr uint64_t auto_rays_per_triangle = 300;
/// Whether "auto" has paid for the kd-tree: frames given `rays` over `triangles` triangles.
inline bool auto_paid_for_rtt(uint64_t rays, uint64_t triangles) {
    return rays >= auto_rays_per_triangle * triangles;
}

struct RenderResult {
    int width = 0;
    int height = 0;
    int aa = 1;
    /// The pixel rows the arrays below hold: all of them from render(), one band from
    /// render_bands() (rows [first_row, first_row + rows), in the same layout).
    int first_row = 0;
    int rows = 0;
    /// Linear RGB per pixel, row-major, y = 0 at the top; box filter of the pixel's samples.
    std::vector<Vec3f> pixels;
    /// CONVENTIONS' RTTH payload (sample order y, x, j, i; invalid_triangle = miss), if asked.
    std::vector<uint32_t> hits;
    /// CONVENTIONS' RTTS payload (bit l = light l visible; 0 for a miss), if asked.
    std::vector<uint32_t> shadows;
    /// One grey level per pixel: 255 * (fraction of its primary samples RTT answered).
    std::vector<uint8_t> primary_map;
    /// One grey level per pixel for one light, averaged over its active segments: 255 answered
    /// with an empty relevant list, 128 answered from a list, 0 traced (0 also: no segment).
    std::vector<uint8_t> shadow_map;
    /// Per pixel, the hit of its first sample (i = j = 0), if asked: t (infinity on a miss) and
    /// the triangle (invalid_triangle on a miss).
    std::vector<float> depth;
    std::vector<uint32_t> first_triangle;
    RenderStats stats;
};

/// Renders `scene` (its lights, materials and background; the camera comes from `options`)
/// through `tracer`, which must have been made over the same scene, filling the answer maps
/// `maps` asks for. Throws rtt::Error for options or maps out of range (their validate()) or a
/// degenerate camera.
RenderResult render(const Scene& scene, const Tracer& tracer, const RenderOptions& options,
                    const AnswerMaps& maps = {});

/// Estimated bytes of one render() with these options and what `rtt render` keeps beside it:
/// the linear pixels, the 8-bit image, the answer maps and the hit and shadow buffers (with the
/// copy the buffer writer makes).
uint64_t render_memory_bytes(const RenderOptions& options, const AnswerMaps& maps = {});

/// Renders the image a band of whole tile rows at a time, in any order and on demand: while
/// next_band(first_tile_row, tile_rows) returns true, renders tile rows [first_tile_row,
/// first_tile_row + tile_rows) (a tile row is 4 pixel rows; the last may be cut by the image)
/// and hands their result to band_done (first_row, rows set; stats empty). Returns the
/// statistics of every band rendered. A band's pixels and buffers are those render() gives
/// for the same rows, bit for bit, whatever the band sizes: a distributed renderer
/// (apps/rtt/mpi_render.cpp) assembles the image from bands rendered on several machines. A
/// band edge also cuts the regions it crosses, so the RTT maps and the answered / traced counts
/// equal render()'s when bands start on multiples of region_pixels() / 4 tile rows.
/// Throws rtt::Error for options or maps out of range or a band outside the image.
RenderStats render_bands(const Scene& scene, const Tracer& tracer, const RenderOptions& options,
                         const std::function<bool(int& first_tile_row, int& tile_rows)>& next_band,
                         const std::function<void(RenderResult& band)>& band_done,
                         const AnswerMaps& maps = {});

/// 8-bit sRGB (R, G, B per pixel) of linear pixels, clamped to [0, 1].
std::vector<uint8_t> encode_srgb8(const std::vector<Vec3f>& pixels);

/// The omni light `--light x,y,z` creates: white, intensity 0.5 * |diagonal of bounds|^2 /
/// light_count, so that a surface about one scene diagonal away receives irradiance of about
/// 0.5 / light_count, whatever the scene's units.
Light make_point_light(const Vec3f& position, const Bbox3f& scene_bounds, size_t light_count);

}  // namespace rtt
