#include "trace/trace_rtt.h"

#include <bit>
#include <cmath>

#include "geom/plane_id.h"
#include "geom/shaft.h"
#include "simd/simd.h"
#include "trace/factories.h"
#include "trace/rtt_corners.h"
#include "trace/rtt_inner.h"
#include "trace/rtt_tile.h"
#include "trace/trace_packet.h"
#include "trace/trace_ray.h"

namespace rtt {
namespace {

/// Inner rays go K at a time: 16 with AVX-512, 8 with AVX2, else 4.
constexpr int inner_width = simd_max_width;
/// Packet width of the fallback for rays RTT does not answer: the widest packets, whose
/// tracer is the fastest (4x4 samples per packet with AVX-512).
constexpr int fallback_width = simd_max_width;
/// Nodes shaft culling may enter for a tile of n samples before RTT gives the tile up: its
/// corners missed much of what the shaft crosses, and tracing is cheaper (measured at K = 1).
constexpr int deferred_budget(int n) { return 8 + n; }
constexpr float unit_roundoff = 0x1p-24f;

/// Per-thread scratch (tracers are called concurrently): the mailbox of the current tile and
/// the corners' result with its list and deferred nodes (too big for the stack of a tile call).
thread_local TriangleMailbox tls_mailbox;
thread_local CornerResult tls_corners;

class RttTracer final : public Tracer {
public:
    /// `extended` ("rtt"): answer tiles whose corners raised the paper's incoherence flag too
    /// (their list is complete anyway, rtt_corners.h), and primary tiles whose corners hit
    /// several triangles of one plane. false ("rtt-paper"): the paper's rules, coherent corners
    /// on one triangle (shadows: coherent corners).
    RttTracer(const Scene& scene, const KdTree& tree, bool extended)
        : tree_(tree), triangles_(gather_triangles(scene)), planes_(compute_plane_ids(triangles_)),
          normals_(triangles_, planes_), extended_(extended) {}
    std::string_view name() const override { return extended_ ? "rtt" : "rtt-paper"; }

    void intersect(const RayTile& tile, std::span<Hit> hits, TraceStats* stats,
                   std::span<SampleAnswer> answers) const override;
    void occluded(const SegmentTile& tile, std::span<uint8_t> visible, TraceStats* stats,
                  std::span<SampleAnswer> answers) const override;

private:
    static bool shaft_tile(bool shaft, int width, int height, size_t n) {
        return shaft && width >= 2 && height >= 2 && size_t(width) * size_t(height) == n &&
               n <= size_t(rtt_max_tile_samples);
    }
    bool one_receiver_plane(const SegmentTile& tile) const;
    uint64_t answer_primary(const RayTile& tile, const Shaft& s, const RelevantList& list, float end_limit,
                            const FacingPlane& end, float end_tol, std::span<Hit> hits,
                            std::span<SampleAnswer> answers, SampleBits& need) const;
    uint64_t answer_shadows(const SegmentTile& tile, const Shaft& s, const RelevantList& list, bool blocked,
                            const FacingPlane& receiver, float receiver_tol, std::span<uint8_t> visible,
                            std::span<SampleAnswer> answers, SampleBits& need) const;

    const KdTree& tree_;
    std::vector<TriangleVerts> triangles_;
    PlaneIds planes_;
    PlaneNormals normals_;
    bool extended_;
};

// ---- primary and reflected rays -----------------------------------------------------------

void RttTracer::intersect(const RayTile& tile, std::span<Hit> hits, TraceStats* stats,
                          std::span<SampleAnswer> answers) const {
    const int n = int(tile.rays.size());
    TraceStats st;
    st.tiles = 1;
    st.rays = uint64_t(n);
    for (SampleAnswer& a : answers) a = SampleAnswer::traced;
    Ray corners[4];
    int cs[4];
    Shaft shaft;
    if (!shaft_tile(tile.shaft, tile.width, tile.height, tile.rays.size()) ||
        !make_shaft(corners_of(tile, corners, cs), shaft)) {
        trace_tile_packets<fallback_width>(tree_, triangles_, tile, hits);
        st.traced = uint64_t(n);
        if (stats) *stats += st;
        return;
    }
    CornerResult& res = tls_corners;
    CornerStatus status = trace_corners<false>(tree_, triangles_, shaft, nullptr, corners, tls_mailbox, res);
    if (status == CornerStatus::untraced) {
        RayPacket<4> p;
        for (int i = 0; i < 4; ++i) p.set(i, corners[i]);
        trace_packet<4>(tree_, triangles_, p, 0xF, res.hit);
    }
    for (int i = 0; i < 4; ++i) hits[cs[i]] = res.hit[i];

    SampleBits need(n);
    uint64_t answered = 0;
    // The paper asks the 4 corners to hit one triangle T. Exact plane identity allows any
    // triangles of one plane P: the inner rays end on P (or before). Along kz, P over the slope
    // quad lies between the corners' hits (1 / offset is affine in the slope), so the region
    // R = cone, offsets up to end_limit, apex side of P (+ end_tol) holds every inner segment
    // up to its answer when that answer lies in R, which answer_primary checks per ray.
    const uint32_t plane = res.hit[0].valid() ? planes_.id[res.hit[0].tri] : no_plane;
    const bool one_plane = plane != no_plane && res.hit[1].valid() && res.hit[2].valid() && res.hit[3].valid() &&
                           planes_.id[res.hit[1].tri] == plane && planes_.id[res.hit[2].tri] == plane &&
                           planes_.id[res.hit[3].tri] == plane;
    FacingPlane end_plane;
    const bool one_triangle = res.hit[1].tri == res.hit[0].tri && res.hit[2].tri == res.hit[0].tri &&
                              res.hit[3].tri == res.hit[0].tri;
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
        if (collect_deferred<false>(tree_, triangles_, shaft, region, deferred_budget(n), tls_mailbox, res) == CornerStatus::traced) {
            // "Beyond the end" (shaft.h test (d)): a triangle whose vertices all lie beyond
            // end_limit along kz cannot be hit inside R.
            RelevantList& list = res.list;
            int kept = 0;
            for (int j = 0; j < list.count; ++j)
                if (!(list.min_offset[j] * (1.f - 16.f * unit_roundoff) > end_limit * (1.f + 4.f * unit_roundoff))) {
                    list.tri[kept] = list.tri[j];
                    list.min_offset[kept++] = list.min_offset[j];
                }
            list.count = kept;
            answered = answer_primary(tile, shaft, list, end_limit, end_plane, end_tol, hits, answers, need);
            st.rtt_tiles = 1;
            st.relevant_sum = uint64_t(list.count);
        } else {
            status = CornerStatus::overflow;
        }
    }
    if (st.rtt_tiles == 0) {
        for (int s = 0; s < n; ++s)
            if (s != cs[0] && s != cs[1] && s != cs[2] && s != cs[3]) need.set(s);
    }
    RayPacket<fallback_width> packet;
    for_each_needed_block<fallback_width>(
        tile.width, tile.height, need, packet, [&](int lane, int s) { packet.set(lane, tile.rays[s]); },
        [&](uint32_t active, const int* sample) {
            Hit out[fallback_width];
            trace_packet<fallback_width>(tree_, triangles_, packet, active, out);
            for (uint32_t b = active; b; b &= b - 1) hits[sample[std::countr_zero(b)]] = out[std::countr_zero(b)];
        });
    st.answered = answered;
    st.traced = uint64_t(n) - answered;
    if (stats) *stats += st;
}

uint64_t RttTracer::answer_primary(const RayTile& tile, const Shaft& s, const RelevantList& list, float end_limit,
                                   const FacingPlane& end, float end_tol, std::span<Hit> hits,
                                   std::span<SampleAnswer> answers, SampleBits& need) const {
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
        ok &= (best.tri != vint<K>(int32_t(invalid_triangle))) & (t * abs(vf::load(b.dir[s.kz])) <= vf(end_limit));
        const Vec3v<K> d = b.direction();
        const vf nx = vf(end.n.x) * d.x, ny = vf(end.n.y) * d.y, nz = vf(end.n.z) * d.z;
        const vf g = vf(end.h) + t * ((nx + ny) + nz);
        const vf err = vf(8.f * unit_roundoff) * (vf(end.h) + t * ((abs(nx) + abs(ny)) + abs(nz)));
        ok &= g - err >= vf(-end_tol);
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

// ---- shadow segments ----------------------------------------------------------------------

/// The paper's condition for a shadow shaft: every sample landed on a triangle of one plane
/// (exact plane identity), and the light is not on that plane (exact orientation).
bool RttTracer::one_receiver_plane(const SegmentTile& tile) const {
    const uint32_t t0 = tile.triangles[0];
    if (t0 >= triangles_.size()) return false;
    const uint32_t pid = planes_.id[t0];
    if (pid == no_plane) return false;
    for (const uint32_t t : tile.triangles)
        if (t >= triangles_.size() || planes_.id[t] != pid) return false;
    const TriangleVerts& r = triangles_[planes_.representative[pid]];
    return orient3d_sign(r.v0, r.v1, r.v2, tile.light) != 0;
}

void RttTracer::occluded(const SegmentTile& tile, std::span<uint8_t> visible, TraceStats* stats,
                         std::span<SampleAnswer> answers) const {
    const int n = int(tile.points.size());
    uint64_t active_count = 0;
    for (int i = 0; i < n; ++i) active_count += tile.active[i] != 0;
    TraceStats st;
    st.tiles = 1;
    st.rays = active_count;
    for (SampleAnswer& a : answers) a = SampleAnswer::traced;
    for (uint8_t& v : visible) v = 0;
    if (active_count == 0) {
        if (stats) *stats += st;
        return;
    }
    Ray corners[4];
    int cs[4];
    Shaft shaft;
    if (!shaft_tile(tile.shaft, tile.width, tile.height, tile.points.size()) || !one_receiver_plane(tile) ||
        !make_shaft(corners_of(tile, corners, cs), shaft)) {
        occluded_tile_packets<fallback_width>(tree_, triangles_, tile, visible);
        st.traced = active_count;
        if (stats) *stats += st;
        return;
    }
    // The region of the answered segments: the shaft between the start and end offsets, and
    // on the light's side of the receiver plane. A segment L + t w, t <= tmax, of a point within
    // receiver_tol of the plane (checked per point: n.w + H >= -receiver_tol) has
    // n . (x - L) = t n.w >= -tmax (H + receiver_tol).
    FacingPlane receiver;
    if (!normals_.facing(planes_.id[tile.triangles[0]], tile.light, receiver)) {
        occluded_tile_packets<fallback_width>(tree_, triangles_, tile, visible);
        st.traced = active_count;
        if (stats) *stats += st;
        return;
    }
    const float tmax = corners[0].tmax;
    const float receiver_tol = (1.f - tmax) * receiver.h * 0.25f;
    ShaftRegion region(shaft, tree_.bounds, shaft.start_lo, shaft.end_hi);
    region.add_end_plane(receiver.n, -tmax * (receiver.h + receiver_tol) * (1.f + 0x1p-20f));
    CornerResult& res = tls_corners;
    CornerStatus status = trace_corners<true>(tree_, triangles_, shaft, &region, corners, tls_mailbox, res);
    if (status == CornerStatus::untraced) {
        RayPacket<4> p;
        for (int i = 0; i < 4; ++i) p.set(i, corners[i]);
        res.occluded = occluded_packet<4>(tree_, triangles_, p, 0xF);
    }
    for (int i = 0; i < 4; ++i)
        if (tile.active[cs[i]]) visible[cs[i]] = !((res.occluded >> i) & 1u);
    if (status == CornerStatus::traced && (extended_ || res.coherent))
        status = collect_deferred<true>(tree_, triangles_, shaft, region, deferred_budget(n), tls_mailbox, res);
    SampleBits need(n);
    uint64_t answered = 0;
    if ((status == CornerStatus::traced && (extended_ || res.coherent)) || status == CornerStatus::blocked) {
        const bool blocked = status == CornerStatus::blocked;
        answered = answer_shadows(tile, shaft, res.list, blocked, receiver, receiver_tol, visible, answers, need);
        st.rtt_tiles = 1;
        st.relevant_sum = blocked ? 1 : uint64_t(res.list.count);
    } else {
        for (int i = 0; i < n; ++i)
            if (tile.active[i] && i != cs[0] && i != cs[1] && i != cs[2] && i != cs[3]) need.set(i);
    }
    RayPacket<fallback_width> packet;
    for_each_needed_block<fallback_width>(
        tile.width, tile.height, need, packet,
        [&](int lane, int s) { packet.set(lane, shadow_ray(tile.light, tile.points[s])); },
        [&](uint32_t active, const int* sample) {
            const uint32_t occ = occluded_packet<fallback_width>(tree_, triangles_, packet, active);
            for (uint32_t b = active; b; b &= b - 1) {
                const int lane = std::countr_zero(b);
                visible[sample[lane]] = !((occ >> lane) & 1u);
            }
        });
    st.answered = answered;
    st.traced = active_count - answered;
    if (stats) *stats += st;
}

uint64_t RttTracer::answer_shadows(const SegmentTile& tile, const Shaft& s, const RelevantList& list, bool blocked,
                                   const FacingPlane& receiver, float receiver_tol, std::span<uint8_t> visible,
                                   std::span<SampleAnswer> answers, SampleBits& need) const {
    constexpr int K = inner_width;
    using vf = vfloat<K>;
    const int n = int(tile.points.size());
    const int c1 = tile.width - 1, c2 = (tile.height - 1) * tile.width, c3 = n - 1;
    const SampleAnswer how = blocked || list.count > 0 ? SampleAnswer::answered_list : SampleAnswer::answered_empty;
    uint64_t answered = 0;
    InnerBatch<K> b;
    const auto flush = [&] {
        const uint32_t used = b.seal();
        const WatertightPacket<K> wp = watertight<K>(b, used);
        vbool<K> ok = shaft_accepts<K>(s, b, wp) & vbool<K>::from_bits(used);
        // The point on the light's side of the receiver plane or within receiver_tol beyond
        // it: v = n.w + H (w = p - L as the segment has it), with its rounding.
        const Vec3v<K> w = b.direction();
        const vf nx = vf(receiver.n.x) * w.x, ny = vf(receiver.n.y) * w.y, nz = vf(receiver.n.z) * w.z;
        const vf v = ((nx + ny) + nz) + vf(receiver.h);
        const vf err = vf(8.f * unit_roundoff) * (((abs(nx) + abs(ny)) + abs(nz)) + vf(receiver.h));
        ok &= v - err >= vf(-receiver_tol);
        vbool<K> occ = vbool<K>(blocked);
        if (!blocked && list.count > 0) occ = occluded_by_list<K>(wp, ok, list, triangles_);
        const uint32_t good = movemask(ok), occ_bits = movemask(occ);
        for (int l = 0; l < b.count; ++l) {
            const int smp = b.sample[l];
            if ((good >> l) & 1u) {
                visible[smp] = !((occ_bits >> l) & 1u);
                if (!answers.empty()) answers[smp] = how;
                ++answered;
            } else {
                need.set(smp);
            }
        }
        b.count = 0;
    };
    for (int i = 1; i < n; ++i) {
        if (i == c1 || i == c2 || i == c3 || !tile.active[i]) continue;
        b.add(i, shadow_ray(tile.light, tile.points[i]));
        if (b.count == K) flush();
    }
    if (b.count) flush();
    return answered;
}

}  // namespace

std::unique_ptr<Tracer> make_rtt_tracer(const Scene& scene, const KdTree& tree) {
    return std::make_unique<RttTracer>(scene, tree, true);
}

std::unique_ptr<Tracer> make_rtt_paper_tracer(const Scene& scene, const KdTree& tree) {
    return std::make_unique<RttTracer>(scene, tree, false);
}

}  // namespace rtt
