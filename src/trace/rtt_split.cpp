// The RTT tracer's quadrant shafts: a big tile RTT cannot answer whole (its corners land on
// several planes) is answered as 4 quadrants, each its own shaft (trace_rtt.h).
#include <bit>
#include <cmath>

#include "trace/rtt_inner.h"
#include "trace/rtt_tracer.h"
#include "trace/trace_packet.h"

namespace rtt::rtt_detail {
namespace {

/// Calls fn(x0, y0, w, h) for the 4 quadrants of a w x h grid.
template <typename Fn>
void for_each_quadrant(int width, int height, Fn&& fn) {
    const int w0 = width / 2, h0 = height / 2;
    fn(0, 0, w0, h0);
    fn(w0, 0, width - w0, h0);
    fn(0, h0, w0, height - h0);
    fn(w0, h0, width - w0, height - h0);
}

/// Per-thread copies of a quadrant's samples, one set per split depth.
struct QuadrantScratch {
    std::vector<Ray> rays;
    std::vector<Hit> hits;
    std::vector<SampleAnswer> answers;
    std::vector<Vec3f> points;
    std::vector<uint32_t> triangles;
    std::vector<uint8_t> active, visible;
};
thread_local QuadrantScratch tls_quadrants[max_split_depth > 0 ? max_split_depth : 1];

}  // namespace

bool RttTracer::split_primary(const RayTile& tile, std::span<Hit> hits,
                              std::span<SampleAnswer> answers, TraceStats& st, int depth) const {
    if (tile.width < split_side || tile.height < split_side || depth >= max_split_depth)
        return false;
    QuadrantScratch& q = tls_quadrants[depth];
    for_each_quadrant(tile.width, tile.height, [&](int x0, int y0, int w, int h) {
        const size_t m = size_t(w) * size_t(h);
        q.rays.resize(m);
        q.hits.resize(m);
        q.answers.resize(answers.empty() ? 0 : m);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                q.rays[size_t(y * w + x)] = tile.rays[size_t((y0 + y) * tile.width + x0 + x)];
        for (SampleAnswer& a : q.answers) a = SampleAnswer::traced;
        intersect_shaft(RayTile{w, h, q.rays, true}, q.hits, q.answers, st, depth + 1);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const size_t to = size_t((y0 + y) * tile.width + x0 + x), from = size_t(y * w + x);
                hits[to] = q.hits[from];
                if (!answers.empty()) answers[to] = q.answers[from];
            }
    });
    return true;
}

bool RttTracer::split_shadows(const SegmentTile& tile, std::span<uint8_t> visible,
                              std::span<SampleAnswer> answers, TraceStats& st, int depth) const {
    if (tile.width < split_side || tile.height < split_side || depth >= max_split_depth)
        return false;
    QuadrantScratch& q = tls_quadrants[depth];
    for_each_quadrant(tile.width, tile.height, [&](int x0, int y0, int w, int h) {
        const size_t m = size_t(w) * size_t(h);
        q.points.resize(m);
        q.triangles.resize(m);
        q.active.resize(m);
        q.visible.resize(m);
        q.answers.resize(answers.empty() ? 0 : m);
        bool any = false;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const size_t from = size_t((y0 + y) * tile.width + x0 + x), to = size_t(y * w + x);
                q.points[to] = tile.points[from];
                q.triangles[to] = tile.triangles[from];
                q.active[to] = tile.active[from];
                any |= q.active[to] != 0;
            }
        if (!any) return;
        for (SampleAnswer& a : q.answers) a = SampleAnswer::traced;
        for (uint8_t& v : q.visible) v = 0;
        occluded_shaft(SegmentTile{w, h, tile.light, q.points, q.triangles, q.active, true},
                       q.visible, q.answers, st, depth + 1);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const size_t to = size_t((y0 + y) * tile.width + x0 + x), from = size_t(y * w + x);
                visible[to] = q.visible[from];
                if (!answers.empty()) answers[to] = q.answers[from];
            }
    });
    return true;
}

}  // namespace rtt::rtt_detail
