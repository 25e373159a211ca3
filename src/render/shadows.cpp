// Shadow segments: one SegmentTile per light over the grid of a traced batch. The tracer sees
// the hit points exactly as CONVENTIONS computes them (p = org + t * dir in float) and the hit
// triangles (RTT decides whether all points lie on one plane by triangle identity).
#include "render/render_internal.h"

namespace rtt::render_detail {

void trace_shadows(const RenderContext& ctx, ThreadStats& ts, const RayBatch& batch,
                   std::span<const Hit> hits, std::span<const SurfacePoint> surf,
                   std::span<uint32_t> lit, PrimaryRecord* record) {
    const size_t n = batch.rays.size();
    const bool every_segment = record && ctx.options.shadow_buffer;
    const int map_light = record ? ctx.maps.shadow_light : -1;
    std::vector<Vec3f> points(n);
    std::vector<uint32_t> triangles(n);
    for (size_t i = 0; i < n; ++i) {
        // A miss has no point; its lane is inactive, the ray origin is a harmless filler.
        points[i] = hits[i].valid() ? surf[i].p : batch.rays[i].org;
        triangles[i] = hits[i].tri;
    }
    std::vector<uint8_t> active(n), lightable(n), visible(n);
    KindStats& kind = ts.kinds[shadow_kind];
    for (size_t l = 0; l < ctx.lights.size(); ++l) {
        bool any = false;
        for (size_t i = 0; i < n; ++i) {
            lightable[i] = hits[i].valid() && can_light(ctx.lights[l], surf[i]);
            active[i] = lightable[i] || (every_segment && hits[i].valid());
            any |= active[i] != 0;
        }
        if (!any) continue;
        const uint32_t bit = 1u << l;
        if (!ctx.options.shadows) {  // validate() keeps buffers and maps away from this mode
            for (size_t i = 0; i < n; ++i)
                if (lightable[i]) lit[i] |= bit;
            continue;
        }
        const SegmentTile tile{batch.width, batch.height, ctx.lights[l].light->position,
                               points,      triangles,    active,
                               batch.shaft, batch.cell};
        std::span<SampleAnswer> answers;
        if (int(l) == map_light) {
            record->shadow_answers.assign(n, SampleAnswer::traced);
            record->shadow_active = active;
            answers = record->shadow_answers;
        }
        timed(kind, [&] { ctx.tracer.occluded(tile, visible, kind.context(answers)); });
        for (size_t i = 0; i < n; ++i) {
            if (!active[i] || !visible[i]) continue;
            if (lightable[i]) lit[i] |= bit;
            if (every_segment) record->visible[i] |= bit;
        }
    }
}

}  // namespace rtt::render_detail
