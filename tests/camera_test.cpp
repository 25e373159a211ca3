// Camera rays against CONVENTIONS' formula, written out here once more in scalar float: the
// renderer's (SIMD) generation must give the same bits for every sample, and so must the
// directions RTT remakes in registers (src/geom/camera_simd.h).
#include "rtt/camera.h"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <numbers>
#include <vector>

#include "geom/camera_simd.h"

namespace rtt {
namespace {

/// CONVENTIONS, "Camera and samples", as written there.
Vec3f conventions_direction(const Camera& c, int W, int H, int K, int x, int y, int i, int j) {
    const Vec3f forward = normalize(c.target - c.position);
    const Vec3f right = normalize(cross(forward, c.up));
    const Vec3f up2 = cross(right, forward);
    const float aspect = float(W) / float(H);
    const float h = std::tan(c.fovy_deg * (std::numbers::pi_v<float> / 180.f) / 2.f);
    const float u = (float(x) + (float(i) + 0.5f) / float(K)) / float(W);
    const float v = (float(y) + (float(j) + 0.5f) / float(K)) / float(H);
    return normalize(forward + (2.f * u - 1.f) * h * aspect * right - (2.f * v - 1.f) * h * up2);
}

bool same_bits(const Vec3f& a, const Vec3f& b) {
    return std::bit_cast<uint32_t>(a.x) == std::bit_cast<uint32_t>(b.x) &&
           std::bit_cast<uint32_t>(a.y) == std::bit_cast<uint32_t>(b.y) &&
           std::bit_cast<uint32_t>(a.z) == std::bit_cast<uint32_t>(b.z);
}

TEST(CameraRays, RegionRaysAreConventionsBitForBit) {
    const Camera cameras[] = {
        {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 50},
        {{1e4f, -3e3f, 2.5e4f}, {1e4f + 1, -3e3f - 0.3f, 2.5e4f - 2}, {0.1f, 1, 0.2f}, 17.5f},
        {{0.3f, 0.1f, -0.7f}, {-5, 2, 9}, {0, 0, 1}, 120},
    };
    size_t mismatches = 0, samples = 0;
    for (const Camera& camera : cameras)
        for (const int K : {1, 2, 3, 4, 6}) {
            const int W = 70, H = 37;  // not multiples of 4: the padding follows the formula
            const CameraRays cam(camera, W, H, K);
            for (const auto [tx, ty, cols, rows] :
                 {std::array{0, 0, 1, 1}, {3, 2, 4, 2}, {17, 9, 1, 1}, {12, 6, 6, 4}}) {
                const int w = 4 * K * cols, h = 4 * K * rows;
                std::vector<Ray> rays(size_t(w) * size_t(h));
                cam.region_rays(tx, ty, cols, rows, rays);
                for (int sr = 0; sr < h; ++sr)
                    for (int sc = 0; sc < w; ++sc) {
                        const Ray& r = rays[size_t(sr) * size_t(w) + size_t(sc)];
                        const Vec3f d = conventions_direction(camera, W, H, K, 4 * tx + sc / K,
                                                              4 * ty + sr / K, sc % K, sr % K);
                        mismatches += !same_bits(r.dir, d) || !same_bits(r.org, camera.position) ||
                                      r.tmin != 0.f || r.tmax != pos_inf;
                        ++samples;
                    }
            }
        }
    EXPECT_GT(samples, 100000u);
    EXPECT_EQ(mismatches, 0u);
}

// camera_directions<K> at every width the build has, lane by lane against the scalar frame.
template <int K>
size_t lane_mismatches(const CameraRays& cam) {
    const CameraTile tile = cam.tile(2, 1);
    const int w = 4 * K;
    std::vector<float> a(static_cast<size_t>(w));
    column_factors(tile, w, a.data());
    size_t bad = 0;
    for (int sr = 0; sr < 8; ++sr) {
        const float b = row_factor(tile, sr);
        for (int sc = 0; sc < w; sc += K) {
            const Vec3v<K> d =
                camera_directions<K>(cam.frame(), vfloat<K>::loadu(&a[size_t(sc)]), b);
            for (int l = 0; l < K; ++l)
                bad += !same_bits(Vec3f{d.x[l], d.y[l], d.z[l]},
                                  cam.frame().direction(a[size_t(sc + l)], b));
        }
    }
    return bad;
}

TEST(CameraRays, SimdDirectionsEqualScalarAtEveryWidth) {
    const CameraRays cam({{2, 1, 7}, {-1, 0.5f, -2}, {0, 1, 0}, 65}, 640, 480, 4);
    EXPECT_EQ(lane_mismatches<4>(cam), 0u);
#ifdef RTT_HAVE_SIMD8
    EXPECT_EQ(lane_mismatches<8>(cam), 0u);
#endif
#ifdef RTT_HAVE_SIMD16
    EXPECT_EQ(lane_mismatches<16>(cam), 0u);
#endif
}

}  // namespace
}  // namespace rtt
