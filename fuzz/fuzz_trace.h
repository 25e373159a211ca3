// What the scene fuzzers do with a scene that loaded: build the kd-tree and trace a small image
// through every tracer kind, which must agree with brute force on every sample (tests/agreement.h;
// embree kinds only have to not crash). Hostile geometry (huge or tiny coordinates, degenerate
// and coincident triangles) thus also checks that nobody's picture silently goes wrong.
#pragma once

#include <string>

#include "agreement.h"
#include "fuzz_util.h"
#include "rtt/camera.h"
#include "rtt/kdtree.h"
#include "rtt/scene.h"

namespace rtt::fuzz {

/// Larger scenes are only loaded and validated (brute force per sample would slow fuzzing).
inline constexpr size_t max_traced_triangles = 4096;

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
    // A degenerate camera (e.g. from coordinates near float's limits) is an rtt::Error.
    for (const auto& [kind, a] : differential::compare_tracers(scene, tree, "brute", view)) {
        if (a.hit_mismatches == 0 && a.shadow_mismatches == 0) continue;
        std::fprintf(stderr, "rtt fuzz: tracer '%s' disagrees with brute force: %s\n",
                     kind.c_str(), a.first_mismatch.c_str());
        std::abort();
    }
}

}  // namespace rtt::fuzz
