// The "bvh" tracer: single rays through the 4-wide BVH (bvh/bvh.h), children tested four at a
// time, nearest first. Exact: a node is skipped only when the ray's interval in its box, widened
// by the kd-tree's split margin, starts after the closest hit so far (docs/design.md, "The BVH
// for arbitrary rays"); triangles are tested with the one watertight test and ties go to the
// smaller index, so hits equal trace_ray's bit for bit.
#include "trace/trace_bvh.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "simd/vfloat4.h"
#include "trace/factories.h"
#include "trace/trace_ray.h"
#include "trace/traced_tile.h"

namespace rtt {
namespace {

/// What the node test needs of a ray, broadcast to four lanes.
struct BoxRay {
    vfloat4 org[3], inv[3];
    vfloat4 t_scale;
    bool flat[3];  ///< dir[a] == 0: a face distance is NaN when the ray lies in the face's plane.
    bool free[3];  ///< |1 / dir[a]| beyond 2^40: the axis is left unbounded (never culls).

    BoxRay(const Ray& ray, const Bbox3f& bounds) {
        for (int a = 0; a < 3; ++a) {
            const float inv_a = 1.f / ray.dir[a];
            org[a] = vfloat4(ray.org[a]);
            inv[a] = vfloat4(inv_a);
            flat[a] = ray.dir[a] == 0.f;
            free[a] = !flat[a] && !(std::fabs(inv_a) <= 0x1p40f);
        }
        t_scale = vfloat4(std::min(scene_t_scale(bounds, ray), FLT_MAX));
    }

    /// Lanes of the node's children whose box the ray may meet in [tmin, tmax]; their entry
    /// distances (widened) in `near`.
    RTT_FORCEINLINE uint32_t test(const Bvh4Node& n, float tmin, float tmax, vfloat4& near) const {
        vfloat4 tn(neg_inf), tf(pos_inf);
        for (int a = 0; a < 3; ++a) {
            if (free[a]) [[unlikely]]
                continue;
            const vfloat4 dlo = (vfloat4::load(n.lo[a]) - org[a]) * inv[a];
            const vfloat4 dhi = (vfloat4::load(n.hi[a]) - org[a]) * inv[a];
            vfloat4 na = min(dlo, dhi), fa = max(dlo, dhi);
            if (flat[a]) [[unlikely]] {  // in a face's plane: inside the closed slab
                const vbool4 in_plane = isnan(dlo) | isnan(dhi);
                na = select(in_plane, vfloat4(neg_inf), na);
                fa = select(in_plane, vfloat4(pos_inf), fa);
            }
            tn = max(tn, na);
            tf = min(tf, fa);
        }
        // The margin of trace_ray's split distances, from finite magnitudes (an infinite
        // distance comes from a zero direction component and is exact).
        const vfloat4 big(FLT_MAX), margin(kd_margin);
        near = tn - (min(abs(tn), big) + t_scale) * margin;
        const vfloat4 far = tf + (min(abs(tf), big) + t_scale) * margin;
        const uint32_t used = (1u << n.count) - 1u;
        return movemask(max(near, vfloat4(tmin)) <= min(far, vfloat4(tmax))) & used;
    }
};

struct StackEntry {
    uint32_t child;
    float near;
};

template <bool AnyHit>
Hit traverse(const Bvh4& bvh, const Ray& ray) {
    Hit best;
    if (bvh.nodes.empty()) return best;
    WatertightRay wr(ray);
    const BoxRay br(ray, padded_bounds(bvh.bounds));
    // Each node pushes at most 3 children: 3 per level, bvh_max_depth levels.
    StackEntry stack[3 * bvh_max_depth + 4];
    int top = 0;
    stack[top++] = {0, ray.tmin};
    while (top > 0) {
        const StackEntry e = stack[--top];
        if (e.near > wr.tmax) continue;  // wr.tmax: the closest hit so far (inclusive)
        if (e.child & bvh_leaf_bit) {
            const uint32_t first = (e.child & ~bvh_leaf_bit) >> 4, count = e.child & 15u;
            for (uint32_t k = first; k < first + count; ++k) {
                float t;
                if (!intersect_watertight(wr, bvh.triangles[k], t)) continue;
                if constexpr (AnyHit) return Hit{t, bvh.ids[k]};
                if (closer(t, bvh.ids[k], best)) {
                    best = {t, bvh.ids[k]};
                    wr.tmax = t;
                }
            }
            continue;
        }
        const Bvh4Node& node = bvh.nodes[e.child];
        vfloat4 near;
        uint32_t mask = br.test(node, ray.tmin, wr.tmax, near);
        if (!mask) continue;
        alignas(16) float d[4];
        store(d, near);
        // Push far to near, so the nearest child is popped next.
        int order[4], n = 0;
        for (; mask; mask &= mask - 1) {
            const int i = std::countr_zero(mask);
            int j = n++;
            for (; j > 0 && d[order[j - 1]] < d[i]; --j) order[j] = order[j - 1];
            order[j] = i;
        }
        for (int j = 0; j < n; ++j) stack[top++] = {node.child[order[j]], d[order[j]]};
    }
    return best;
}

class BvhTracer final : public Tracer {
public:
    explicit BvhTracer(const Scene& scene) : bvh_(build_bvh4(gather_triangles(scene))) {}
    std::string_view name() const override { return "bvh"; }

    void intersect(const RayTile& tile, std::span<Hit> hits, TraceStats* stats,
                   std::span<SampleAnswer> answers) const override {
        intersect_one_by_one(tile, hits, stats, answers,
                             [&](const Ray& ray) { return traverse<false>(bvh_, ray); });
    }

    void occluded(const SegmentTile& tile, std::span<uint8_t> visible, TraceStats* stats,
                  std::span<SampleAnswer> answers) const override {
        occluded_one_by_one(tile, visible, stats, answers,
                            [&](const Ray& ray) { return traverse<true>(bvh_, ray).valid(); });
    }

private:
    Bvh4 bvh_;
};

}  // namespace

Hit trace_bvh(const Bvh4& bvh, const Ray& ray) {
    return traverse<false>(bvh, ray);
}

bool occluded_bvh(const Bvh4& bvh, const Ray& ray) {
    return traverse<true>(bvh, ray).valid();
}

std::unique_ptr<Tracer> make_bvh_tracer(const Scene& scene, const KdTree&) {
    return std::make_unique<BvhTracer>(scene);
}

}  // namespace rtt
