// One batch of rays from generation to colour: closest hits, shadow segments, local shading,
// reflections (recursively, one batch per depth).
#include "render/render_internal.h"

namespace rtt::render_detail {

void trace_batch(const RenderContext& ctx, ThreadStats& ts, const RayBatch& batch, int depth,
                 std::span<Vec3f> colors, PrimaryRecord* record) {
    const size_t n = batch.rays.size();
    std::vector<Hit> hits(n);
    const RayTile tile{batch.width, batch.height, batch.rays, batch.shaft, batch.cell};
    KindStats& kind = ts.kinds[depth == 0 ? primary_kind : secondary_kind];
    std::span<SampleAnswer> answers;
    if (record && ctx.maps.primary) {
        record->primary_answers.assign(n, SampleAnswer::traced);
        answers = record->primary_answers;
    }
    timed(kind, [&] { ctx.tracer.intersect(tile, hits, kind.context(answers)); });
    ts.rays_by_depth[size_t(depth)] += n;

    std::vector<SurfacePoint> surf(n);
    for (size_t i = 0; i < n; ++i)
        if (hits[i].valid()) surf[i] = surface_at(ctx, batch.rays[i], hits[i]);

    std::vector<uint32_t> lit(n, 0);
    if (record && ctx.options.shadow_buffer) record->visible.assign(n, 0);
    trace_shadows(ctx, ts, batch, hits, surf, lit, record);

    for (size_t i = 0; i < n; ++i)
        colors[i] =
            hits[i].valid() ? shade(ctx, surf[i], batch.rays[i].dir, lit[i]) : ctx.scene.background;

    trace_reflections(ctx, ts, batch, hits, surf, depth, colors);
    if (record) record->hits = std::move(hits);
}

}  // namespace rtt::render_detail
