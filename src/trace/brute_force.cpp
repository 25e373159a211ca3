#include "trace/brute_force.h"

namespace rtt {

Hit trace_brute_force(std::span<const TriangleVerts> triangles, const Ray& ray) {
    const WatertightRay wr(ray);
    Hit best;
    for (uint32_t i = 0; i < triangles.size(); ++i) {
        float t;
        if (intersect_watertight(wr, triangles[i], t) && closer(t, i, best)) best = {t, i};
    }
    return best;
}

bool occluded_brute_force(std::span<const TriangleVerts> triangles, const Ray& ray) {
    const WatertightRay wr(ray);
    for (const TriangleVerts& tri : triangles) {
        float t;
        if (intersect_watertight(wr, tri, t)) return true;
    }
    return false;
}

}  // namespace rtt

// ---- the oracle behind the Tracer interface ("brute"), for tests and tiny scenes ----------
#include "trace/factories.h"
#include "trace/traced_tile.h"

namespace rtt {
namespace {

class BruteForceTracer final : public Tracer {
public:
    explicit BruteForceTracer(const Scene& scene) : triangles_(gather_triangles(scene)) {}
    std::string_view name() const override { return "brute"; }

    void intersect(const RayTile& tile, std::span<Hit> hits,
                   const TraceContext& context) const override {
        intersect_one_by_one(tile, hits, context,
                             [&](const Ray& ray) { return trace_brute_force(triangles_, ray); });
    }

    void occluded(const SegmentTile& tile, std::span<uint8_t> visible,
                  const TraceContext& context) const override {
        occluded_one_by_one(tile, visible, context,
                            [&](const Ray& ray) { return occluded_brute_force(triangles_, ray); });
    }

private:
    TriangleArray triangles_;
};

}  // namespace

std::unique_ptr<Tracer> make_brute_force_tracer(const Scene& scene, const KdTree&) {
    return std::make_unique<BruteForceTracer>(scene);
}

}  // namespace rtt
