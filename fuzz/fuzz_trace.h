// What the scene fuzzers do with a scene that loaded: build the kd-tree and trace a small image
// through every tracer kind. Every kind must agree with the reference tracer "ray" on every
// sample, hits and shadow bits (tests/agreement.h; embree kinds only have to not crash), and,
// in views where float can resolve the scene at all (resolvable()), "ray" with brute force on
// every primary sample whose brute-force hit is geometrically meaningful. Hostile
// geometry (huge or tiny coordinates, degenerate and coincident triangles) thus also checks that
// no picture silently goes wrong.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "agreement.h"
#include "fuzz_util.h"
#include "rtt/camera.h"
#include "rtt/kdtree.h"
#include "rtt/scene.h"

namespace rtt::fuzz {

/// Larger scenes are only loaded and validated (brute force per sample would slow fuzzing).
inline constexpr size_t max_traced_triangles = 4096;

/// False when the scene is smaller than 1e-4 of the coordinates around it: float then cannot
/// place the geometry reliably (at 1e-8, camera 1e8 away from a box of size 2,
/// corpus/fuzz_cli_values/camera_1e8_away, the kd-tree tracers miss what the brute-force test
/// "hits" through rounding), so brute force is no oracle there. The kd-tree tracers must still
/// agree with "ray" at any distance. (Far views found three real bugs, now regression tests in
/// tests/far_view_test.cpp: the box-clip distances are rounded at the origin's magnitude, far
/// coarser than the tree's padding, and cut off hits on the bounds in "ray", the packet tracers
/// and the RTT corner traversal, seeds camera_11469_away_tie, camera_3e7_away_tie,
/// camera_5720_away_rtt_miss, camera_6e7_away_rtt_miss; and an RTT shadow rule,
/// camera_990_away_rtt_shadow.)
inline bool resolvable(const Scene& scene, const Camera& camera) {
    const Bbox3f box = scene.bounds();
    const Vec3f d = box.diagonal();
    const auto max_abs = [](const Vec3f& v) {
        return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
    };
    const float scale = std::max({max_abs(box.lo), max_abs(box.hi), max_abs(camera.position)});
    return std::max({d.x, d.y, d.z}) >= 1e-4f * scale;
}

/// Aborts (a libFuzzer crash) when a tracer disagrees; throws rtt::Error for a degenerate camera.
inline void compare_all(const Scene& scene, const KdTree& tree,
                        const differential::AgreementView& view) {
    for (const auto& [kind, a] : differential::compare_tracers(scene, tree, "ray", view)) {
        // Brute force is held to "ray" below, on the samples where its answer means something.
        if (kind == "brute" || (a.hit_mismatches == 0 && a.shadow_mismatches == 0)) continue;
        std::fprintf(stderr, "rtt fuzz: tracer '%s' disagrees with 'ray': %s\n", kind.c_str(),
                     a.first_mismatch.c_str());
        std::abort();
    }
    if (!resolvable(scene, view.camera)) return;
    const differential::BruteAgreement b =
        differential::compare_with_brute(scene, tree, "ray", view);
    if (b.mismatches == 0) return;
    std::fprintf(stderr, "rtt fuzz: 'ray' disagrees with brute force: %s\n",
                 b.first_mismatch.c_str());
    std::abort();
}

inline void trace_and_compare(const Scene& scene) {
    if (scene.triangle_count() > max_traced_triangles) return;
    const KdTree tree = build_kdtree(scene);
    differential::AgreementView view;
    view.camera = scene.camera ? *scene.camera : default_camera_for(scene.bounds());
    view.width = 8;
    view.height = 6;  // padded to 8: padding samples are traced too
    for (const Light& l : scene.lights) view.lights.push_back(l.position);
    if (view.lights.empty()) view.lights.push_back(view.camera.position);
    if (view.lights.size() > 2) view.lights.resize(2);
    compare_all(scene, tree, view);
}

}  // namespace rtt::fuzz
