// The RTT tracer's shadow segments (rtt_tracer.h).
#include <algorithm>
#include <bit>
#include <cmath>

#include "relevant_triangles/inner_rays.h"
#include "relevant_triangles/rtt_tracer.h"
#include "relevant_triangles/tolerances.h"
#include "relevant_triangles/walk.h"
#include "simd/lane_bytes.h"
#include "trace/packet_blocks.h"
#include "trace/trace_bvh.h"
#include "trace/trace_packet.h"

namespace rtt {
inline namespace RTT_ISA_NS {
namespace rtt_detail {

// ---- shadow segments ----------------------------------------------------------------------

/// The paper's condition for a shadow shaft: the samples landed on triangles of one plane
/// (exact plane identity), and the light is not on that plane (exact orientation). The corners
/// must (their points span the shaft); other samples only when active: an inactive sample has
/// no segment, and an active one on P lies inside the corners' quad on P (the primary rays of
/// the grid are inside their pyramid), which answer_shadows checks per segment anyway.
bool RttTracer::one_receiver_plane(const SegmentTile& tile) const {
    const uint32_t t0 = tile.triangles[0];
    if (t0 >= triangles_.size()) return false;
    const uint32_t pid = planes_.id[t0];
    if (pid == no_plane) return false;
    const auto on_plane = [&](uint32_t t) { return t < triangles_.size() && planes_.id[t] == pid; };
    for (int i = 1; i < 4; ++i)
        if (!on_plane(tile.triangles[corner_sample(tile.width, tile.height, i)])) return false;
    // Neighbouring samples mostly hit the same triangle: its plane is looked up once.
    uint32_t checked = t0;
    for (size_t i = 0; i < tile.triangles.size(); ++i) {
        const uint32_t t = tile.triangles[i];
        if (t == checked || !tile.active[i]) continue;
        if (!on_plane(t)) return false;
        checked = t;
    }
    const TriangleVerts& r = triangles_[planes_.representative[pid]];
    return orient3d_sign(r.v0, r.v1, r.v2, tile.light) != 0;
}

void RttTracer::occluded(const SegmentTile& tile, std::span<uint8_t> visible,
                         const TraceContext& context) const {
    const std::span<SampleAnswer> answers = context.answers;
    const int n = int(tile.points.size());
    uint64_t active_count = 0;
    for (int i = 0; i < n; ++i) active_count += tile.active[i] != 0;
    RttStats st;
    for (SampleAnswer& a : answers) a = SampleAnswer::traced;
    for (uint8_t& v : visible) v = 0;
    if (active_count == 0) {
    } else if (!shaft_tile(tile.shaft, tile.width, tile.height, tile.points.size())) {
        const FallbackClock clock(st.fallback_ns);
        if (!tile.shaft && bvh_pays(loose_rays_, loose_rays_per_triangle, active_count)) {
            BlockerCache blockers;
            visible_bvh_segments(bvh(), tile, visible, blockers);
            st.bvh_rays += active_count;
        } else {
            BlockerCache blockers;
            occluded_tile_packets<fallback_width>(tree_, triangles_, tile, visible, nullptr,
                                                  &blockers);
        }
        count_decline(st, Decline::no_shaft);
    } else {
        occluded_shaft(tile, visible, answers, st);
    }
    record_tile(active_count, st, context);
}

void RttTracer::trace_declined(const SegmentTile& tile, std::span<uint8_t> visible,
                               BlockerCache& blockers, uint64_t active, RttStats& st) const {
    if (options_.shadow_fallback == ShadowFallback::bvh &&
        bvh_pays(declined_rays_, declined_rays_per_triangle, active)) {
        visible_bvh_segments(bvh(), tile, visible, blockers);
        st.bvh_rays += active;
    } else {
        occluded_tile_packets<fallback_width>(tree_, triangles_, tile, visible, nullptr, &blockers);
    }
}

namespace {

/// True when the end point L + w of a segment lies on the light's side of the receiver plane
/// or within `tol` beyond it: v = n.w + H, with its rounding (answer_shadows' check, one ray).
bool near_receiver(const FacingPlane& receiver, float tol, const Vec3f& w) {
    const float nx = receiver.n.x * w.x, ny = receiver.n.y * w.y, nz = receiver.n.z * w.z;
    const float v = ((nx + ny) + nz) + receiver.h;
    const float err =
        8.f * unit_roundoff * (((std::fabs(nx) + std::fabs(ny)) + std::fabs(nz)) + receiver.h);
    return v - err >= -tol;
}

}  // namespace

void RttTracer::occluded_shaft(const SegmentTile& tile, std::span<uint8_t> visible,
                               std::span<SampleAnswer> answers, RttStats& st) const {
    const int n = int(tile.points.size());
    Ray corners[4];
    int cs[4];
    Shaft shaft;
    BlockerCache blockers;
    // The region of the answered segments: the shaft between the start and end offsets, and
    // on the light's side of the receiver plane. A segment L + t w, t <= tmax, of a point within
    // receiver_tol of the plane (checked per point: n.w + H >= -receiver_tol) has
    // n . (x - L) = t n.w >= -tmax (H + receiver_tol).
    const auto trace_all = [&](Decline why) {
        const FallbackClock clock(st.fallback_ns);
        uint64_t active = 0;
        for (const uint8_t a : tile.active) active += a != 0;
        trace_declined(tile, visible, blockers, active, st);
        count_decline(st, why);
    };
    FacingPlane receiver;
    if (!one_receiver_plane(tile) ||
        !normals_.facing(planes_.id[tile.triangles[0]], tile.light, receiver))
        return trace_all(Decline::no_end);
    if (!make_shaft(corners_of(tile, corners, cs), shaft)) return trace_all(Decline::no_shaft);
    const float tmax = corners[0].tmax;
    const float receiver_tol = (1.f - tmax) * receiver.h * tolerance::receiver_gap;
    ShaftRegion region(shaft, tree_.bounds, shaft.start_lo, shaft.end_hi);
    region.add_end_plane(receiver.n, -tmax * (receiver.h + receiver_tol) * (1.f + 0x1p-20f));
    CornerResult& res = tls_corners;
    CornerStatus status;
    if (extended_) {
        // The region is final from the start: one walk through it (walk.h) answers the
        // corners and builds the list. The corners' answers come from the region, so their
        // points must pass the receiver check the inner ones pass (a point computed far from
        // the scene may lie off the plane by more than the tolerance). A walk that gives up
        // leaves the whole tile to packets.
        for (int i = 0; i < 4; ++i)
            if (!near_receiver(receiver, receiver_tol, corners[i].dir))
                return trace_all(Decline::no_end);
        status = cull_shaft<Query::any_hit>(
            tree_, triangles_, shaft, region,
            walk_budget(n, is_region(tile.width, tile.height, tile.cell), true), tls_mailbox, res,
            [](const PacketHit<4>&, ShaftRegion&) { return Narrowed::same; });
        if (status == CornerStatus::untraced) return trace_all(res.declined);
    } else {
        status = trace_corners<Query::any_hit>(tree_, triangles_, shaft, &region, corners,
                                               tls_mailbox, res);
        if (status == CornerStatus::untraced) {
            RayPacket<4> p;
            for (int i = 0; i < 4; ++i) p.set(i, corners[i]);
            res.occluded = occluded_packet<4>(tree_, triangles_, p, 0xF);
        }
    }
    for (int i = 0; i < 4; ++i)
        if (tile.active[cs[i]]) visible[cs[i]] = !((res.occluded >> i) & 1u);
    if (status == CornerStatus::traced && !extended_ && res.coherent)
        status = collect_deferred<Query::any_hit>(tree_, triangles_, shaft, region,
                                                  deferred_budget(n), tls_mailbox, res);
    SampleBits need(n);
    if ((status == CornerStatus::traced && (extended_ || res.coherent)) ||
        status == CornerStatus::blocked) {
        const bool blocked = status == CornerStatus::blocked;
        st.answered += answer_shadows(tile, shaft, res.list, blocked, receiver, receiver_tol,
                                      visible, answers, need);
        st.rtt_tiles += 1;
        st.relevant_sum += blocked ? 1 : uint64_t(res.list.count);
    } else {
        count_decline(st, status == CornerStatus::traced ? Decline::corners_parted : res.declined);
        for (int i = 0; i < n; ++i)
            if (tile.active[i] && i != cs[0] && i != cs[1] && i != cs[2] && i != cs[3]) need.set(i);
    }
    if (need.none(n)) return;
    const FallbackClock clock(st.fallback_ns);
    for_each_segment_block<fallback_width>(
        tile, [&](int s) { return need.test(s); },
        [&](const RayPacket<fallback_width>& packet, uint32_t active, const int* sample) {
            const uint32_t occ = occluded_packet<fallback_width>(tree_, triangles_, packet, active,
                                                                 nullptr, &blockers);
            for (uint32_t b = active; b; b &= b - 1) {
                const int lane = std::countr_zero(b);
                visible[sample[lane]] = !((occ >> lane) & 1u);
            }
        });
}

uint64_t RttTracer::answer_shadows(const SegmentTile& tile, const Shaft& s,
                                   const RelevantList& list, bool blocked,
                                   const FacingPlane& receiver, float receiver_tol,
                                   std::span<uint8_t> visible, std::span<SampleAnswer> answers,
                                   SampleBits& need) const {
    constexpr int K = inner_width;
    using vf = vfloat<K>;
    const int n = int(tile.points.size());
    const SampleAnswer how =
        blocked || list.count > 0 ? SampleAnswer::answered_list : SampleAnswer::answered_empty;
    uint64_t answered = 0;
    const ApexList apex_list(s, list, triangles_);
    for (int base = 0; base < n; base += K) {
        const InnerRays<K> r = load_inner_segments<K>(tile.light, tile.points, base);
        const uint32_t lanes = without_corners(r, tile.width, tile.height) &
                               nonzero_bytes(tile.active.data() + base, std::min(K, n - base));
        if (!lanes) continue;
        const WatertightPacket<K> wp = watertight<K>(r, lanes);
        vbool<K> ok = shaft_accepts<K>(s, r, wp) & vbool<K>::from_bits(lanes);
        // The point on the light's side of the receiver plane or within receiver_tol beyond
        // it: v = n.w + H (w = p - L as the segment has it), with its rounding.
        const Vec3v<K>& w = r.dir;
        const vf nx = vf(receiver.n.x) * w.x, ny = vf(receiver.n.y) * w.y,
                 nz = vf(receiver.n.z) * w.z;
        const vf v = ((nx + ny) + nz) + vf(receiver.h);
        const vf err = vf(8.f * unit_roundoff) * (((abs(nx) + abs(ny)) + abs(nz)) + vf(receiver.h));
        ok &= v - err >= vf(-receiver_tol);
        vbool<K> occ = vbool<K>(blocked);
        if (!blocked && list.count > 0) occ = occluded_by_list<K>(wp, ok, apex_list);
        const uint32_t good = movemask(ok), occ_bits = movemask(occ);
        need.set_lanes(base, lanes & ~good);
        answered += uint64_t(std::popcount(good));
        if (good == all_lanes<K>) {  // a whole block: its 16 bytes at once
            store_bits_as_bytes<K>(visible.data() + base, ~occ_bits & all_lanes<K>);
            if (!answers.empty()) std::fill_n(answers.begin() + base, K, how);
            continue;
        }
        for (uint32_t b = good; b; b &= b - 1) {
            const int l = std::countr_zero(b);
            visible[size_t(base + l)] = !((occ_bits >> l) & 1u);
            if (!answers.empty()) answers[size_t(base + l)] = how;
        }
    }
    return answered;
}

}  // namespace rtt_detail
}  // namespace RTT_ISA_NS
}  // namespace rtt
