// Reflected rays. The representation (see include/rtt/render.h) keeps RTT's shaft for planar
// mirrors and never hands the tracer an inactive lane.
//
// Planar shaft. Reflection about the plane n.x = d is the affine map M(x) = x - 2 (n.x - d) n,
// whose linear part R(v) = v - 2 (n.v) n is an isometry. A parent ray org + t dir that hits
// the mirror at t_hit continues, mirrored, as M(org + t dir) = M(org) + t R(dir) for t > t_hit.
// So every reflected ray of the tile starts at one apex E' = M(org) with direction R(dir) and
// the same parameter t: R is linear, so directions on a planar grid stay on a planar grid and
// the 4 corner rays still bound every inner ray (docs/design.md, "Primary and reflected rays"). The
// rays start just beyond the mirror, at t_hit (1 + delta): those points are the mirror's points
// scaled about E' by 1 + delta, hence again on one plane, as RTT's start test needs.
//
// How big delta must be: E' and the start points carry rounding of a few ulps of
// M = |E| + |E'| + t; delta t_hit must exceed it with room to spare (32 eps M), or the mirror
// itself would be found again. 1e-4 covers ordinary scenes; the second term covers scenes far
// from the origin. A tile needing delta > 1e-2 (a camera almost on the mirror) is packed
// instead. As with any epsilon, a ray grazing the mirror (error / sin(angle)) may still meet it.
#include <algorithm>
#include <cfloat>
#include <cmath>

#include "render/render_internal.h"

namespace rtt::render_detail {
namespace {

float max_abs(const Vec3f& v) {
    return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
}

Vec3f reflect(const Vec3f& dir, const Vec3f& n) {
    return dir - n * (2.f * dot(dir, n));
}

/// Builds the planar-shaft reflected tile; false when the tile does not qualify.
bool build_shaft_batch(const RenderContext& ctx, const RayBatch& parent, std::span<const Hit> hits,
                       RayBatch& child) {
    const Plane plane = triangle_plane(triangle_verts(ctx.scene, hits[0].tri));
    if (!is_finite(plane.n) || !std::isfinite(plane.d)) return false;
    float t_min = pos_inf, t_max = 0.f;
    for (const Hit& h : hits) {
        if (h.tri != hits[0].tri) {
            const Plane q = triangle_plane(triangle_verts(ctx.scene, h.tri));
            if (!(q.n == plane.n) || !(q.d == plane.d)) return false;
        }
        t_min = std::min(t_min, h.t);
        t_max = std::max(t_max, h.t);
    }
    const Vec3f eye = parent.rays[0].org;
    const Vec3f mirrored_eye = eye - plane.n * (2.f * (dot(plane.n, eye) - plane.d));
    if (!is_finite(mirrored_eye) || !(t_min > 0.f)) return false;
    const float delta = std::max(
        1e-4f, 32.f * FLT_EPSILON * (max_abs(eye) + max_abs(mirrored_eye) + t_max) / t_min);
    if (!(delta <= 1e-2f)) return false;
    child.width = parent.width;
    child.height = parent.height;
    child.shaft = true;
    child.rays.resize(parent.rays.size());
    for (size_t i = 0; i < parent.rays.size(); ++i)
        child.rays[i] = Ray{mirrored_eye, reflect(parent.rays[i].dir, plane.n),
                            hits[i].t * (1.f + delta), pos_inf};
    return true;
}

/// The reflections of one 4x4-pixel tile (or of a batch that is not a region).
void reflect_tile(const RenderContext& ctx, ThreadStats& ts, const RayBatch& batch,
                  std::span<const Hit> hits, std::span<const SurfacePoint> surf, int depth,
                  std::span<Vec3f> colors) {
    std::vector<uint32_t> mirror_samples;
    for (size_t i = 0; i < hits.size(); ++i)
        if (hits[i].valid() && surf[i].material->mirror > 0.f)
            mirror_samples.push_back(uint32_t(i));
    if (mirror_samples.empty()) return;
    if (depth >= ctx.options.max_depth) {
        for (uint32_t i : mirror_samples) colors[i] *= 1.f - surf[i].material->mirror;
        return;
    }

    RayBatch child;
    const bool whole_tile = mirror_samples.size() == hits.size();
    if (!(batch.shaft && whole_tile && build_shaft_batch(ctx, batch, hits, child))) {
        // Packed: only the mirror samples, in tile order, as one row; no shaft.
        child.width = int(mirror_samples.size());
        child.height = 1;
        child.shaft = false;
        child.rays.clear();
        for (uint32_t i : mirror_samples)
            child.rays.push_back(Ray{surf[i].p, reflect(batch.rays[i].dir, surf[i].ns),
                                     ctx.reflect_epsilon, pos_inf});
    }

    std::vector<Vec3f> reflected(child.rays.size());
    trace_batch(ctx, ts, child, depth + 1, reflected, nullptr);
    for (size_t k = 0; k < mirror_samples.size(); ++k) {
        const uint32_t i = mirror_samples[k];
        const float m = surf[i].material->mirror;
        colors[i] = colors[i] * (1.f - m) + reflected[child.shaft ? i : k] * m;
    }
}

}  // namespace

void trace_reflections(const RenderContext& ctx, ThreadStats& ts, const RayBatch& batch,
                       std::span<const Hit> hits, std::span<const SurfacePoint> surf, int depth,
                       std::span<Vec3f> colors) {
    const int c = batch.cell;
    if (c == 0 || (batch.width == c && batch.height == c)) {
        reflect_tile(ctx, ts, batch, hits, surf, depth, colors);
        return;
    }
    // A region: each 4x4-pixel tile reflects on its own, so that the reflected rays (whether
    // a tile forms a mirror shaft, its start offset delta) do not depend on the region size.
    bool mirrors = false;
    for (size_t i = 0; i < hits.size(); ++i)
        mirrors |= hits[i].valid() && surf[i].material->mirror > 0.f;
    if (!mirrors) return;
    RayBatch cell{c, c, batch.shaft, std::vector<Ray>(size_t(c) * size_t(c))};
    std::vector<Hit> cell_hits(cell.rays.size());
    std::vector<SurfacePoint> cell_surf(cell.rays.size());
    std::vector<Vec3f> cell_colors(cell.rays.size());
    for (int y0 = 0; y0 < batch.height; y0 += c)
        for (int x0 = 0; x0 < batch.width; x0 += c) {
            const auto at = [&](int r, int i) {
                return size_t(y0 + r) * size_t(batch.width) + size_t(x0 + i);
            };
            for (int r = 0; r < c; ++r)
                for (int i = 0; i < c; ++i) {
                    const size_t k = size_t(r) * size_t(c) + size_t(i);
                    cell.rays[k] = batch.rays[at(r, i)];
                    cell_hits[k] = hits[at(r, i)];
                    cell_surf[k] = surf[at(r, i)];
                    cell_colors[k] = colors[at(r, i)];
                }
            reflect_tile(ctx, ts, cell, cell_hits, cell_surf, depth, cell_colors);
            for (int r = 0; r < c; ++r)
                for (int i = 0; i < c; ++i)
                    colors[at(r, i)] = cell_colors[size_t(r) * size_t(c) + size_t(i)];
        }
}

}  // namespace rtt::render_detail
