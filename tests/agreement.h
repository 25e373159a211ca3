// Every tracer kind against a reference, sample for sample, on the batches the renderer makes
// (render.h): per 4x4-pixel tile a 4K x 4K RayTile in CONVENTIONS' sample order restricted to
// the tile (sample row y*K+j, column x*K+i), shaft = true; per light a SegmentTile from the
// reference's hits (p = org + t dir, the hit triangles, every hit sample active, shaft = true).
// All kinds get the same segment tiles, so shadow bits are compared on identical segments.
//
// Used by tests/degenerate_test.cpp and by the fuzz targets (fuzz/), which run it on whatever
// geometry the fuzzer produced.
//
// Embree kinds ("embree", "embree1") break exact ties (equal t) their own way, so they are run
// (they must not crash) but not compared.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "rtt/camera.h"
#include "rtt/kdtree.h"
#include "rtt/tracer.h"

namespace rtt::differential {

struct AgreementView {
    Camera camera;
    int width = 8;
    int height = 8;
    int aa = 1;
    std::vector<Vec3f> lights;
};

struct Agreement {
    uint64_t samples = 0;         ///< Primary samples compared.
    uint64_t hits = 0;            ///< Of those, reference hits.
    uint64_t hit_mismatches = 0;  ///< Different triangle or t (bit for bit).
    uint64_t segments = 0;        ///< Active shadow segments compared.
    uint64_t shadow_mismatches = 0;
    std::string first_mismatch;  ///< Where the first mismatch was, for the failure message.
};

/// True for kinds that are run but not held to exact agreement (see the file comment).
inline bool tie_breaks_differ(const std::string& kind) {
    return kind.rfind("embree", 0) == 0;
}

/// The primary rays of tile (tx, ty), exactly as the renderer builds them.
inline std::vector<Ray> primary_tile(const CameraRays& cam, int tx, int ty) {
    std::vector<Ray> rays(size_t(16) * size_t(cam.aa()) * size_t(cam.aa()));
    cam.tile_rays(tx, ty, rays);
    return rays;
}

/// Runs every kind of tracer_kinds() over the view and compares it with `reference` ("brute",
/// or "ray" for scenes too big for brute force). Returns one entry per kind, the reference
/// included (compared with itself: a second run must give the same answers). Embree kinds get
/// an entry with zero counts. Throws rtt::Error for a degenerate camera.
inline std::map<std::string, Agreement> compare_tracers(const Scene& scene, const KdTree& tree,
                                                        const std::string& reference,
                                                        const AgreementView& view) {
    const CameraRays cam(view.camera, view.width, view.height, view.aa);
    const int side = 4 * view.aa;
    const size_t n = size_t(side) * size_t(side);
    const std::unique_ptr<Tracer> ref = make_tracer(reference, scene, tree);
    std::map<std::string, std::unique_ptr<Tracer>> tracers;
    std::map<std::string, Agreement> out;
    for (const std::string& kind : tracer_kinds()) {
        tracers[kind] = make_tracer(kind, scene, tree);
        out[kind];
    }

    std::vector<Hit> want(n), got(n);
    std::vector<Vec3f> points(n);
    std::vector<uint32_t> tris(n);
    std::vector<uint8_t> active(n), vis_want(n), vis_got(n);
    for (int ty = 0; ty < (view.height + 3) / 4; ++ty)
        for (int tx = 0; tx < (view.width + 3) / 4; ++tx) {
            const std::vector<Ray> rays = primary_tile(cam, tx, ty);
            const RayTile tile{side, side, rays, true};
            ref->intersect(tile, want);
            for (size_t i = 0; i < n; ++i) {
                points[i] = want[i].valid() ? rays[i].org + want[i].t * rays[i].dir : rays[i].org;
                tris[i] = want[i].tri;
                active[i] = want[i].valid();
            }
            std::vector<std::vector<uint8_t>> visible_want(view.lights.size());
            for (size_t l = 0; l < view.lights.size(); ++l) {
                const SegmentTile seg{side, side, view.lights[l], points, tris, active, true};
                ref->occluded(seg, vis_want);
                visible_want[l] = vis_want;
            }
            for (auto& [kind, tracer] : tracers) {
                Agreement& a = out[kind];
                const bool compare = !tie_breaks_differ(kind);
                tracer->intersect(tile, got);
                for (size_t i = 0; compare && i < n; ++i) {
                    ++a.samples;
                    a.hits += want[i].valid();
                    if (got[i].tri == want[i].tri &&
                        std::bit_cast<uint32_t>(got[i].t) == std::bit_cast<uint32_t>(want[i].t))
                        continue;
                    if (a.hit_mismatches++ == 0)
                        a.first_mismatch =
                            "tile (" + std::to_string(tx) + "," + std::to_string(ty) + ") sample " +
                            std::to_string(i) + ": triangle " + std::to_string(got[i].tri) + " t " +
                            std::to_string(got[i].t) + ", " + reference + " says " +
                            std::to_string(want[i].tri) + " t " + std::to_string(want[i].t);
                }
                for (size_t l = 0; l < view.lights.size(); ++l) {
                    const SegmentTile seg{side, side, view.lights[l], points, tris, active, true};
                    tracer->occluded(seg, vis_got);
                    for (size_t i = 0; compare && i < n; ++i) {
                        if (!active[i]) continue;
                        ++a.segments;
                        if (vis_got[i] == visible_want[l][i]) continue;
                        if (a.shadow_mismatches++ == 0 && a.first_mismatch.empty())
                            a.first_mismatch =
                                "shadow, tile (" + std::to_string(tx) + "," + std::to_string(ty) +
                                ") sample " + std::to_string(i) + " light " + std::to_string(l) +
                                ": " + std::to_string(vis_got[i]) + ", " + reference + " says " +
                                std::to_string(visible_want[l][i]);
                    }
                }
            }
        }
    return out;
}

/// True when brute force's hit `h` of `ray` is geometrically meaningful: its point lies in the
/// hit triangle's bounding box widened by 1e-3 of the box's size plus float's resolution at the
/// box's and the origin's coordinates. Not so for rays grazing a triangle's plane: there the
/// watertight test's u, v, w are rounding noise of one sign and t = T / det (det ~ 0) is
/// arbitrary, e.g. a "hit" at t = 6.2 whose point is 0.6 outside the triangle
/// (fuzz/corpus/fuzz_mesh/grazing_diagonal_plane.obj). No kd-tree traversal visits such a point,
/// so these samples are left out of the comparison with brute force (and counted).
inline bool plausible_brute_hit(const Scene& scene, const Ray& ray, const Hit& h) {
    if (!h.valid()) return true;
    const TriangleIndices& idx = scene.triangles[h.tri];
    Bbox3f box;
    for (uint32_t v : idx) box.extend(scene.vertices[v]);
    const Vec3f p = ray.org + h.t * ray.dir;
    const auto max_abs = [](const Vec3f& v) {
        return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
    };
    const Vec3f d = box.diagonal();
    const float pad = 1e-3f * std::max({d.x, d.y, d.z}) +
                      1e-5f * std::max({max_abs(box.lo), max_abs(box.hi), max_abs(ray.org),
                                        h.t * max_abs(ray.dir)});
    for (int a = 0; a < 3; ++a)
        if (!(p[a] >= box.lo[a] - pad && p[a] <= box.hi[a] + pad)) return false;
    return true;
}

/// Primary samples of the view on which `reference` and brute force disagree (closest triangle
/// and t, bit for bit), leaving out the brute-force hits plausible_brute_hit() rejects; those are
/// counted in `excluded`.
struct BruteAgreement {
    uint64_t samples = 0, mismatches = 0, excluded = 0;
    std::string first_mismatch;
};

inline BruteAgreement compare_with_brute(const Scene& scene, const KdTree& tree,
                                         const std::string& reference, const AgreementView& view) {
    const CameraRays cam(view.camera, view.width, view.height, view.aa);
    const int side = 4 * view.aa;
    const size_t n = size_t(side) * size_t(side);
    const std::unique_ptr<Tracer> ref = make_tracer(reference, scene, tree);
    const std::unique_ptr<Tracer> brute = make_tracer("brute", scene, tree);
    std::vector<Hit> got(n), want(n);
    BruteAgreement out;
    for (int ty = 0; ty < (view.height + 3) / 4; ++ty)
        for (int tx = 0; tx < (view.width + 3) / 4; ++tx) {
            const std::vector<Ray> rays = primary_tile(cam, tx, ty);
            const RayTile tile{side, side, rays, true};
            ref->intersect(tile, got);
            brute->intersect(tile, want);
            for (size_t i = 0; i < n; ++i) {
                ++out.samples;
                if (!plausible_brute_hit(scene, rays[i], want[i])) {
                    ++out.excluded;
                    continue;
                }
                if (got[i].tri == want[i].tri &&
                    std::bit_cast<uint32_t>(got[i].t) == std::bit_cast<uint32_t>(want[i].t))
                    continue;
                if (out.mismatches++ == 0)
                    out.first_mismatch = "tile (" + std::to_string(tx) + "," + std::to_string(ty) +
                                         ") sample " + std::to_string(i) + ": " + reference +
                                         " says triangle " + std::to_string(got[i].tri) + " t " +
                                         std::to_string(got[i].t) + ", brute force " +
                                         std::to_string(want[i].tri) + " t " +
                                         std::to_string(want[i].t);
            }
        }
    return out;
}

}  // namespace rtt::differential
