// The RTT tracer: tiles of primary and reflected rays, and the factory (rtt_tracer.h).
#include <algorithm>
#include <bit>
#include <cmath>
#include <optional>
#include <string>
#include <type_traits>

#include "relevant_triangles/inner_rays.h"
#include "relevant_triangles/rtt_tracer.h"
#include "relevant_triangles/tolerances.h"
#include "relevant_triangles/walk.h"
#include "rtt/error.h"
#include "trace/factories.h"
#include "trace/packet_blocks.h"
#include "trace/trace_bvh.h"
#include "trace/trace_frustum.h"
#include "trace/trace_packet.h"
#include "trace/traced_tile.h"

namespace rtt {
inline namespace RTT_ISA_NS {
namespace rtt_detail {

// ---- primary and reflected rays -----------------------------------------------------------

void RttTracer::intersect(const RayTile& tile, std::span<Hit> hits,
                          const TraceContext& context) const {
    const int n = int(tile.rays.size());
    const std::span<SampleAnswer> answers = context.answers;
    RttStats st;
    for (SampleAnswer& a : answers) a = SampleAnswer::traced;
    if (!shaft_tile(tile.shaft, tile.width, tile.height, tile.rays.size())) {
        const FallbackClock clock(st.fallback_ns);
        if (!tile.shaft && spread(tile.rays) &&
            bvh_pays(loose_rays_, loose_rays_per_triangle, tile.rays.size())) {
            trace_bvh_tile(bvh(), tile, hits);
            st.bvh_rays += uint64_t(n);
        } else {
            trace_tile_packets<fallback_width>(tree_, triangles_, tile, hits);
        }
        count_decline(st, Decline::no_shaft);
    } else {
        intersect_shaft(tile, hits, answers, st);
    }
    record_tile(uint64_t(n), st, context);
}

const Bvh<bvh_width>& RttTracer::bvh() const {
    std::call_once(bvh_once_, [&] {
        bvh_ = std::make_unique<const Bvh<bvh_width>>(build_bvh<bvh_width>(triangles_));
        bvh_built_.store(true, std::memory_order_release);
    });
    return *bvh_;
}

bool RttTracer::spread(std::span<const Ray> rays) {
    // Packets pay while their rays' directions stay within a narrow cone about the first one.
    const Vec3f d0 = rays.empty() ? Vec3f{} : rays[0].dir;
    const float len0 = length(d0);
    for (const Ray& r : rays)
        if (!(dot(r.dir, d0) >= loose_cos_max * length(r.dir) * len0)) return true;
    return false;
}

bool RttTracer::bvh_pays(std::atomic<uint64_t>& seen, double per_triangle, size_t rays) const {
    if (bvh_built_.load(std::memory_order_acquire)) return true;
    // Once the rays it would take reach per_triangle per triangle, the build has cost about
    // what it saves them.
    const uint64_t total = seen.fetch_add(rays, std::memory_order_relaxed) + rays;
    return double(total) >= per_triangle * double(triangles_.size());
}

void RttTracer::intersect_arbitrary(std::span<const Ray> rays, std::span<Hit> hits,
                                    TraceStats* stats) const {
    trace_bvh_rays(bvh(), rays, hits);
    record_traced_tile(rays.size(), stats);
}

void RttTracer::visible_arbitrary(std::span<const Ray> rays, std::span<uint8_t> visible,
                                  TraceStats* stats) const {
    visible_bvh_rays(bvh(), rays, visible);
    record_traced_tile(rays.size(), stats);
}

/// The end of a primary shaft's region when all 4 corners hit triangles of one plane P seen
/// from the apex (exact plane identity, geom/plane_id.h; the paper asks for one triangle): the
/// inner rays end on P (or before). Along kz, P over the slope quad lies between the corners'
/// hits (1 / offset is affine in the slope), so the region R = cone, offsets up to end_limit,
/// apex side of P (+ end_tol) holds every inner segment up to its answer when that answer lies
/// in R, which answer_primary checks per ray.
bool RttTracer::primary_end(const Shaft& shaft, const Ray (&corners)[4], const vfloat4& t,
                            const vint4& tri, PrimaryEnd& e) const {
    e.plane_id = no_plane;
    for (int i = 0; i < 4; ++i)
        if (uint32_t(tri[i]) >= triangles_.size()) return false;  // a miss
    float end = 0.f, dist = 0.f;
    for (int i = 0; i < 4; ++i) {
        end = std::max(end, t[i] * std::fabs(corners[i].dir[shaft.kz]));
        dist = std::max(dist, t[i] * length(corners[i].dir));
    }
    e.end_limit = end * (1.f + tolerance::end_offset);
    const uint32_t plane = planes_.id[uint32_t(tri[0])];
    for (int i = 1; i < 4; ++i)
        if (plane == no_plane || planes_.id[uint32_t(tri[i])] != plane) return true;
    if (!normals_.facing(plane, shaft.org, e.plane)) return true;
    e.plane_id = plane;
    e.end_tol = tolerance::end_plane * (e.plane.h + dist);
    return true;
}

bool RttTracer::primary_end(const Shaft& shaft, const Ray (&corners)[4], const Hit (&hits)[4],
                            PrimaryEnd& e) const {
    alignas(16) float t[4];
    alignas(16) int32_t tri[4];
    for (int i = 0; i < 4; ++i) {
        t[i] = hits[i].t;
        tri[i] = int32_t(hits[i].tri);
    }
    return primary_end(shaft, corners, vfloat4::load(t), vint4::load(tri), e);
}

void RttTracer::narrow_to(ShaftRegion& region, const PrimaryEnd& e) const {
    const bool plane = e.plane_id != no_plane;
    region.set_end(e.end_limit, plane ? &e.plane.n : nullptr,
                   plane ? -(e.plane.h + e.end_tol) * (1.f + 0x1p-20f) : 0.f);
}

ShaftRegion RttTracer::primary_region(const Shaft& shaft, const PrimaryEnd& e) const {
    ShaftRegion region(shaft, tree_.bounds, shaft.start_lo, e.end_limit);
    narrow_to(region, e);
    return region;
}

void RttTracer::intersect_shaft(const RayTile& tile, std::span<Hit> hits,
                                std::span<SampleAnswer> answers, RttStats& st) const {
    const int n = int(tile.rays.size());
    PrimaryShaft p;
    corners_of(tile, p.corners, p.cs);
    // The list procedure: the paper's under its rules; under rtt's, the lean pass for small
    // tiles from the apex, else the walk.
    const ListProcedure procedure = !extended_ ? ListProcedure::paper
                                    : takes_lean_pass(n, options_.lean_max_samples, p.corners)
                                        ? ListProcedure::lean
                                        : ListProcedure::walk;
    // The lean pass builds the slope quad only when it first needs it (most that give up do
    // not).
    const bool shaft = procedure == ListProcedure::lean ? make_shaft_corners(p.corners, p.shaft)
                                                        : make_shaft(p.corners, p.shaft);
    const ListOutcome outcome = !shaft                             ? ListOutcome::untraced
                                : procedure == ListProcedure::lean ? list_lean(tile, p)
                                : procedure == ListProcedure::walk ? list_walk(tile, p)
                                                                   : list_paper(tile, p);
    if (!shaft) p.declined = Decline::no_shaft;
    if (outcome == ListOutcome::untraced) {
        const FallbackClock clock(st.fallback_ns);
        trace_declined(tile, p.corners, hits, st);
        count_decline(st, p.declined);
        return;
    }
    CornerResult& res = tls_corners;
    for (int i = 0; i < 4; ++i) hits[p.cs[i]] = res.hit[i];

    SampleBits need(n);
    if (outcome == ListOutcome::listed) {
        // "Beyond the end" (conservative_tests.h, test (d)): a triangle whose vertices all lie
        // beyond end_limit along kz cannot be hit inside R; nor can one whose bounding box misses R
        // (the walk's own rule, walk.h; the walk may have listed it under a larger region).
        RelevantList& list = res.list;
        const PrimaryEnd& end = p.end;
        if (!p.open && !p.region) p.region.emplace(primary_region(p.shaft, end));
        int kept = p.open ? list.count : 0;  // the walk's region was the final one
        for (int j = kept; j < list.count; ++j) {
            const TriangleVerts& tri = triangles_[list.tri[j]];
            BoxV box;
            box.lo = min(min(BoxV::lanes(tri.v0), BoxV::lanes(tri.v1)), BoxV::lanes(tri.v2));
            box.hi = max(max(BoxV::lanes(tri.v0), BoxV::lanes(tri.v1)), BoxV::lanes(tri.v2));
            if (!(list.min_offset[j] * (1.f - 16.f * unit_roundoff) >
                  end.end_limit * (1.f + 4.f * unit_roundoff)) &&
                p.region->meets(box)) {
                list.tri[kept] = list.tri[j];
                list.min_offset[kept++] = list.min_offset[j];
            }
        }
        list.count = kept;
        const uint64_t answered = answer_primary(tile, p.shaft, list, end.end_limit,
                                                 end.plane_id != no_plane ? &end.plane : nullptr,
                                                 end.end_tol, hits, answers, need);
        st.rtt_tiles += 1;
        st.relevant_sum += uint64_t(list.count);
        st.answered += answered;
        if (p.open) {
            st.open_tiles += 1;
            st.empty_tiles += uint64_t(list.count == 0);
        }
    } else {
        // Declined after the corners: the whole tile as one packet again (the corners' answers
        // are rewritten, unchanged) costs less than the inner rays 16 at a time.
        count_decline(st, p.declined);
        const FallbackClock clock(st.fallback_ns);
        trace_declined(tile, p.corners, hits, st);
        return;
    }
    if (need.none(n)) return;
    const FallbackClock clock(st.fallback_ns);
    for_each_ray_block<fallback_width>(
        tile, [&](int s) { return need.test(s); },
        [&](const RayPacket<fallback_width>& packet, uint32_t active, const int* sample) {
            Hit out[fallback_width];
            trace_packet<fallback_width>(tree_, triangles_, packet, active, out);
            for (uint32_t b = active; b; b &= b - 1)
                hits[sample[std::countr_zero(b)]] = out[std::countr_zero(b)];
        });
}

void RttTracer::trace_declined(const RayTile& tile, const Ray (&corners)[4], std::span<Hit> hits,
                               RttStats& st) const {
    // Through the BVH's packets once it is built (docs/benchmarks.md, "RTT's fallback");
    // until then one large kd-tree packet up to 2 degrees, the 16-ray packets beyond.
    if (bvh_pays(declined_rays_, declined_rays_per_triangle, tile.rays.size())) {
        trace_bvh_tile(bvh(), tile, hits);
        st.bvh_rays += uint64_t(tile.rays.size());
        return;
    }
    const auto angle = [](const Vec3f& a, const Vec3f& b) {
        return std::acos(std::clamp(dot(a, b) / (length(a) * length(b)), -1.f, 1.f));
    };
    constexpr float narrow_radians = 2.f * 3.14159265f / 180.f;
    const float diagonal =
        std::max(angle(corners[0].dir, corners[3].dir), angle(corners[1].dir, corners[2].dir));
    if (!(diagonal < narrow_radians &&
          trace_frustum(tree_, triangles_, tile.rays, tile.width, tile.height, hits))) {
        trace_tile_packets<fallback_width>(tree_, triangles_, tile, hits);
    }
}

uint64_t RttTracer::answer_primary(const RayTile& tile, const Shaft& s, const RelevantList& list,
                                   float end_limit, const FacingPlane* end, float end_tol,
                                   std::span<Hit> hits, std::span<SampleAnswer> answers,
                                   SampleBits& need) const {
    constexpr int K = inner_width;
    using vf = vfloat<K>;
    const int n = int(tile.rays.size());
    uint64_t answered = 0;
    const ApexList apex_list(s, list, triangles_);
    for (int base = 0; base < n; base += K) {
        const InnerRays<K> r = load_inner_rays<K>(tile.rays, base);
        const uint32_t lanes = without_corners(r, tile.width, tile.height);
        if (!lanes) continue;
        const WatertightPacket<K> wp = watertight<K>(r, lanes);
        vbool<K> ok = shaft_accepts<K>(s, r, wp) & vbool<K>::from_bits(lanes);
        const PacketHit<K> best = closest_in_list<K>(wp, ok, apex_list);
        // Taken only when the answer lies inside R (its offset, and the distance
        // g = h + t n.d of the hit point from P, with its rounding): the segment up to it is
        // in R, so nothing outside the list can come first.
        const vf t = best.t;
        const vf dz = abs(r.dir[s.kz]);
        // Without an end (end_limit = +inf) R is the whole cone beyond the start and the list
        // complete for it: a miss in the list is the ray's answer.
        if (end_limit != pos_inf)
            ok &= (best.tri != vint<K>(int32_t(invalid_triangle))) & (t * dz <= vf(end_limit));
        // g is affine along the ray: checking the answer and the start (reflected rays start
        // away from the apex) covers the whole segment.
        if (end) {
            const Vec3v<K>& d = r.dir;
            const vf nx = vf(end->n.x) * d.x, ny = vf(end->n.y) * d.y, nz = vf(end->n.z) * d.z;
            const vf nd = (nx + ny) + nz, and_ = (abs(nx) + abs(ny)) + abs(nz);
            const vf g = vf(end->h) + t * nd, g0 = vf(end->h) + r.tmin * nd;
            const vf err = vf(8.f * unit_roundoff) * (vf(end->h) + t * and_);
            const vf err0 = vf(8.f * unit_roundoff) * (vf(end->h) + r.tmin * and_);
            ok &= (g - err >= vf(-end_tol)) & (g0 - err0 >= vf(-end_tol));
        }
        const uint32_t good = movemask(ok);
        need.set_lanes(base, lanes & ~good);
        answered += uint64_t(std::popcount(good));
        if (good == all_lanes<K>) {
            // A whole block (most of a tile from K = 3 on): the hits as two vector stores; lane
            // by lane, each scalar read waited on the vector store before it.
            static_assert(sizeof(Hit) == 2 * sizeof(float) && std::is_standard_layout_v<Hit>);
            storeu_pairs(reinterpret_cast<float*>(hits.data() + base), best.t, as_float(best.tri));
            if (!answers.empty())
                std::fill_n(answers.begin() + base, K, SampleAnswer::answered_list);
            continue;
        }
        alignas(64) float ts[K];
        alignas(64) int32_t tris[K];
        store(ts, best.t);
        store(tris, best.tri);
        for (uint32_t b = good; b; b &= b - 1) {
            const int l = std::countr_zero(b);
            hits[size_t(base + l)] = Hit{ts[l], uint32_t(tris[l])};
            if (!answers.empty()) answers[size_t(base + l)] = SampleAnswer::answered_list;
        }
    }
    return answered;
}

}  // namespace rtt_detail

}  // namespace RTT_ISA_NS
}  // namespace rtt
