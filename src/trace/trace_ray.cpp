#include "trace/trace_ray.h"

#include <cmath>

#include "trace/factories.h"
#include "trace/traced_tile.h"

namespace rtt {

Bbox3f padded_bounds(const Bbox3f& box) {
    const Vec3f d = box.diagonal();
    const float extent = std::max(std::max(d.x, d.y), d.z);
    const Vec3f pad =
        Vec3f(extent * kd_box_pad) + abs(box.lo) * kd_box_pad + abs(box.hi) * kd_box_pad;
    return {box.lo - pad, box.hi + pad};
}

float scene_t_scale(const Bbox3f& box, const Ray& ray) {
    float dist = 0.f;
    for (int a = 0; a < 3; ++a)
        dist =
            std::max({dist, std::fabs(box.lo[a] - ray.org[a]), std::fabs(box.hi[a] - ray.org[a])});
    const Vec3f ad = abs(ray.dir);
    return dist / std::max({ad.x, ad.y, ad.z});
}

namespace {

/// Clips [t0, t1] to the padded box, then widens what the box cut by the split margin for
/// `t_scale` (trace_ray.h); returns false when nothing is left.
bool clip_to_box(const Bbox3f& box, const Vec3f& org, const Vec3f& inv, float t_scale, float& t0,
                 float& t1) {
    float lo = t0, hi = t1;
    for (int a = 0; a < 3; ++a) {
        float tn = (box.lo[a] - org[a]) * inv[a];
        float tf = (box.hi[a] - org[a]) * inv[a];
        if (tn > tf) std::swap(tn, tf);
        if (tn > lo) lo = tn;  // a NaN comparison is false: NaN never shrinks the interval
        if (tf < hi) hi = tf;
    }
    if (lo > t0) t0 = std::max(t0, lo - (std::fabs(lo) + t_scale) * kd_margin);
    if (hi < t1) t1 = std::min(t1, hi + (std::fabs(hi) + t_scale) * kd_margin);
    return t0 <= t1;
}

struct StackEntry {
    uint32_t node;
    float t0, t1;
};

template <bool AnyHit>
Hit traverse(const KdTree& tree, std::span<const TriangleVerts> triangles, const Ray& ray) {
    Hit best;
    if (tree.nodes.empty()) return best;
    WatertightRay wr(ray);
    const Vec3f inv{1.f / ray.dir.x, 1.f / ray.dir.y, 1.f / ray.dir.z};
    const int first_is_above[3] = {std::signbit(ray.dir.x), std::signbit(ray.dir.y),
                                   std::signbit(ray.dir.z)};
    float t0 = ray.tmin, t1 = ray.tmax;
    const Bbox3f box = padded_bounds(tree.bounds);
    const float t_scale = scene_t_scale(box, ray);
    if (!clip_to_box(box, ray.org, inv, t_scale, t0, t1)) return best;

    StackEntry stack[kd_max_depth + 1];
    int top = 0;
    stack[top++] = {0, t0, t1};
    const KdNode* nodes = tree.nodes.data();
    while (top > 0) {
        StackEntry e = stack[--top];
        if (e.t0 > best.t) continue;
        uint32_t index = e.node;
        float ta = e.t0, tb = e.t1;
        while (!nodes[index].is_leaf()) {
            const KdNode& n = nodes[index];
            const int axis = n.axis();
            const uint32_t below = index + 1, above = n.above_child();
            const uint32_t first = first_is_above[axis] ? above : below;
            const uint32_t second = first_is_above[axis] ? below : above;
            const float d = (n.split - ray.org[axis]) * inv[axis];
            if (std::isnan(d)) [[unlikely]] {
                stack[top++] = {second, ta, tb};
                index = first;
                continue;
            }
            // d = +-inf from a zero direction component (origin off the plane) is exact: the ray
            // never crosses the plane, so no margin (inf * margin would visit both children).
            // An overflowing 1 / tiny component keeps the infinite margin: both, conservatively.
            const float m = ray.dir[axis] == 0.f ? 0.f : (std::fabs(d) + t_scale) * kd_margin;
            const float first_hi = std::min(tb, d + m);
            const float second_lo = std::max(ta, d - m);
            const bool visit_first = ta <= first_hi;
            const bool visit_second = second_lo <= tb;
            if (visit_first && visit_second) {
                stack[top++] = {second, second_lo, tb};
                index = first;
                tb = first_hi;
            } else if (visit_first) {
                index = first;
                tb = first_hi;
            } else if (visit_second) {
                index = second;
                ta = second_lo;
            } else {
                index = invalid_triangle;  // interval empty (cannot happen for ta <= tb)
                break;
            }
        }
        if (index == invalid_triangle) continue;
        const KdNode& leaf = nodes[index];
        const uint32_t* ids = tree.leaf_triangles.data() + leaf.first_triangle();
        for (uint32_t k = 0, n = leaf.triangle_count(); k < n; ++k) {
            const uint32_t id = ids[k];
            float t;
            if (!intersect_watertight(wr, triangles[id], t)) continue;
            if constexpr (AnyHit) return Hit{t, id};
            if (closer(t, id, best)) {
                best = {t, id};
                wr.tmax = t;  // inclusive: a later equal-t hit still reaches the index tie-break
            }
        }
    }
    return best;
}

class RayTracer final : public Tracer {
public:
    RayTracer(const Scene& scene, const KdTree& tree)
        : tree_(tree), triangles_(gather_triangles(scene)) {}
    std::string_view name() const override { return "ray"; }

    void intersect(const RayTile& tile, std::span<Hit> hits,
                   const TraceContext& context) const override {
        intersect_one_by_one(tile, hits, context,
                             [&](const Ray& ray) { return trace_ray(tree_, triangles_, ray); });
    }

    void occluded(const SegmentTile& tile, std::span<uint8_t> visible,
                  const TraceContext& context) const override {
        occluded_one_by_one(tile, visible, context,
                            [&](const Ray& ray) { return occluded_ray(tree_, triangles_, ray); });
    }

    void visible_arbitrary(std::span<const Ray> rays, std::span<uint8_t> visible,
                           TraceStats* stats) const override {
        for (size_t i = 0; i < rays.size(); ++i)
            visible[i] = !occluded_ray(tree_, triangles_, rays[i]);
        record_traced_tile(rays.size(), stats);
    }

private:
    const KdTree& tree_;
    TriangleArray triangles_;
};

}  // namespace

Hit trace_ray(const KdTree& tree, std::span<const TriangleVerts> triangles, const Ray& ray) {
    return traverse<false>(tree, triangles, ray);
}

bool occluded_ray(const KdTree& tree, std::span<const TriangleVerts> triangles, const Ray& ray) {
    return traverse<true>(tree, triangles, ray).valid();
}

std::unique_ptr<Tracer> make_ray_tracer(const Scene& scene, const KdTree& tree) {
    return std::make_unique<RayTracer>(scene, tree);
}

}  // namespace rtt
