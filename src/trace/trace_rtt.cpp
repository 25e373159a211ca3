// The RTT tracer: tiles of primary and reflected rays, and the factories (trace_rtt.h).
#include "trace/trace_rtt.h"

#include <bit>
#include <cmath>

#include "trace/factories.h"
#include "trace/rtt_inner.h"
#include "trace/rtt_tracer.h"
#include "trace/trace_packet.h"

namespace rtt {
namespace rtt_detail {

// ---- primary and reflected rays -----------------------------------------------------------

void RttTracer::intersect(const RayTile& tile, std::span<Hit> hits, TraceStats* stats,
                          std::span<SampleAnswer> answers) const {
    const int n = int(tile.rays.size());
    TraceStats st;
    for (SampleAnswer& a : answers) a = SampleAnswer::traced;
    if (!shaft_tile(tile.shaft, tile.width, tile.height, tile.rays.size())) {
        trace_tile_packets<fallback_width>(tree_, triangles_, tile, hits);
    } else {
        intersect_shaft(tile, hits, answers, st);
    }
    st.tiles = 1;
    st.rays = uint64_t(n);
    st.traced = uint64_t(n) - st.answered;
    if (stats) *stats += st;
}

void RttTracer::intersect_shaft(const RayTile& tile, std::span<Hit> hits,
                                std::span<SampleAnswer> answers, TraceStats& st) const {
    const int n = int(tile.rays.size());
    Ray corners[4];
    int cs[4];
    Shaft shaft;
    if (!make_shaft(corners_of(tile, corners, cs), shaft)) {
        trace_tile_packets<fallback_width>(tree_, triangles_, tile, hits);
        return;
    }
    CornerResult& res = tls_corners;
    CornerStatus status =
        trace_corners<false>(tree_, triangles_, shaft, nullptr, corners, tls_mailbox, res);
    if (status == CornerStatus::untraced) {
        RayPacket<4> p;
        for (int i = 0; i < 4; ++i) p.set(i, corners[i]);
        trace_packet<4>(tree_, triangles_, p, 0xF, res.hit);
    }
    for (int i = 0; i < 4; ++i) hits[cs[i]] = res.hit[i];

    SampleBits need(n);
    uint64_t answered = 0;
    bool listed = false;
    // The paper asks the 4 corners to hit one triangle T. Exact plane identity allows any
    // triangles of one plane P: the inner rays end on P (or before). Along kz, P over the slope
    // quad lies between the corners' hits (1 / offset is affine in the slope), so the region
    // R = cone, offsets up to end_limit, apex side of P (+ end_tol) holds every inner segment
    // up to its answer when that answer lies in R, which answer_primary checks per ray.
    const uint32_t plane = res.hit[0].valid() ? planes_.id[res.hit[0].tri] : no_plane;
    const bool one_plane = plane != no_plane && res.hit[1].valid() && res.hit[2].valid() &&
                           res.hit[3].valid() && planes_.id[res.hit[1].tri] == plane &&
                           planes_.id[res.hit[2].tri] == plane &&
                           planes_.id[res.hit[3].tri] == plane;
    FacingPlane end_plane;
    const bool one_triangle = res.hit[1].tri == res.hit[0].tri &&
                              res.hit[2].tri == res.hit[0].tri && res.hit[3].tri == res.hit[0].tri;
    const bool qualifies = extended_ ? one_plane : (one_plane && one_triangle && res.coherent);
    if (qualifies && status == CornerStatus::traced &&
        normals_.facing(plane, shaft.org, end_plane)) {
        float end = 0.f, dist = 0.f;
        for (int i = 0; i < 4; ++i) {
            end = std::max(end, res.hit[i].t * std::fabs(corners[i].dir[shaft.kz]));
            dist = std::max(dist, res.hit[i].t * length(corners[i].dir));
        }
        const float end_limit = end * (1.f + 0x1p-10f);
        const float end_tol = 0x1p-14f * (end_plane.h + dist);
        ShaftRegion region(shaft, tree_.bounds, shaft.start_lo, end_limit);
        region.add_end_plane(end_plane.n, -(end_plane.h + end_tol) * (1.f + 0x1p-20f));
        if (collect_deferred<false>(tree_, triangles_, shaft, region, deferred_budget(n),
                                    tls_mailbox, res) == CornerStatus::traced) {
            // "Beyond the end" (shaft.h test (d)): a triangle whose vertices all lie beyond
            // end_limit along kz cannot be hit inside R.
            RelevantList& list = res.list;
            int kept = 0;
            for (int j = 0; j < list.count; ++j)
                if (!(list.min_offset[j] * (1.f - 16.f * unit_roundoff) >
                      end_limit * (1.f + 4.f * unit_roundoff))) {
                    list.tri[kept] = list.tri[j];
                    list.min_offset[kept++] = list.min_offset[j];
                }
            list.count = kept;
            answered = answer_primary(tile, shaft, list, end_limit, end_plane, end_tol, hits,
                                      answers, need);
            st.rtt_tiles += 1;
            st.relevant_sum += uint64_t(list.count);
            st.answered += answered;
            listed = true;
        }
    }
    if (!listed) {
        for (int s = 0; s < n; ++s)
            if (s != cs[0] && s != cs[1] && s != cs[2] && s != cs[3]) need.set(s);
    }
    RayPacket<fallback_width> packet;
    for_each_needed_block<fallback_width>(
        tile.width, tile.height, need, packet,
        [&](int lane, int s) { packet.set(lane, tile.rays[s]); },
        [&](uint32_t active, const int* sample) {
            Hit out[fallback_width];
            trace_packet<fallback_width>(tree_, triangles_, packet, active, out);
            for (uint32_t b = active; b; b &= b - 1)
                hits[sample[std::countr_zero(b)]] = out[std::countr_zero(b)];
        });
}

uint64_t RttTracer::answer_primary(const RayTile& tile, const Shaft& s, const RelevantList& list,
                                   float end_limit, const FacingPlane& end, float end_tol,
                                   std::span<Hit> hits, std::span<SampleAnswer> answers,
                                   SampleBits& need) const {
    constexpr int K = inner_width;
    using vf = vfloat<K>;
    const int n = int(tile.rays.size());
    const int c1 = tile.width - 1, c2 = (tile.height - 1) * tile.width, c3 = n - 1;
    uint64_t answered = 0;
    InnerBatch<K> b;
    const auto flush = [&] {
        const uint32_t used = b.seal();
        const WatertightPacket<K> wp = watertight<K>(b, used);
        vbool<K> ok = shaft_accepts<K>(s, b, wp) & vbool<K>::from_bits(used);
        const PacketHit<K> best = closest_in_list<K>(wp, ok, list, triangles_);
        // Taken only when the answer lies inside R (its offset, and the distance
        // g = h + t n.d of the hit point from P, with its rounding): the segment up to it is
        // in R, so nothing outside the list can come first.
        const vf t = best.t;
        ok &= (best.tri != vint<K>(int32_t(invalid_triangle))) &
              (t * abs(vf::load(b.dir[s.kz])) <= vf(end_limit));
        // g is affine along the ray: checking the answer and the start (reflected rays start
        // away from the apex) covers the whole segment.
        const Vec3v<K> d = b.direction();
        const vf nx = vf(end.n.x) * d.x, ny = vf(end.n.y) * d.y, nz = vf(end.n.z) * d.z;
        const vf nd = (nx + ny) + nz, and_ = (abs(nx) + abs(ny)) + abs(nz);
        const vf t0 = vf::load(b.tmin);
        const vf g = vf(end.h) + t * nd, g0 = vf(end.h) + t0 * nd;
        const vf err = vf(8.f * unit_roundoff) * (vf(end.h) + t * and_);
        const vf err0 = vf(8.f * unit_roundoff) * (vf(end.h) + t0 * and_);
        ok &= (g - err >= vf(-end_tol)) & (g0 - err0 >= vf(-end_tol));
        const uint32_t good = movemask(ok);
        for (int l = 0; l < b.count; ++l) {
            const int smp = b.sample[l];
            if ((good >> l) & 1u) {
                hits[smp] = Hit{best.t[l], uint32_t(best.tri[l])};
                if (!answers.empty()) answers[smp] = SampleAnswer::answered_list;
                ++answered;
            } else {
                need.set(smp);
            }
        }
        b.count = 0;
    };
    for (int i = 1; i < n; ++i) {
        if (i == c1 || i == c2 || i == c3) continue;
        b.add(i, tile.rays[i]);
        if (b.count == K) flush();
    }
    if (b.count) flush();
    return answered;
}

}  // namespace rtt_detail

std::unique_ptr<Tracer> make_rtt_tracer(const Scene& scene, const KdTree& tree) {
    return std::make_unique<rtt_detail::RttTracer>(scene, tree, true);
}

std::unique_ptr<Tracer> make_rtt_paper_tracer(const Scene& scene, const KdTree& tree) {
    return std::make_unique<rtt_detail::RttTracer>(scene, tree, false);
}

}  // namespace rtt
