// Tile-level helpers of the RTT tracer (trace_rtt.cpp): which samples still need tracing, the
// corner rays of a tile, the packet fallback over the samples left, and the plane a shaft's
// rays end on.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "geom/plane_id.h"
#include "geom/shaft.h"
#include "rtt/tracer.h"
#include "trace/trace_packet.h"

namespace rtt {

/// Largest tile RTT takes on: 4x4 pixels with 16 x 16 antialiasing.
inline constexpr int rtt_max_tile_samples = 64 * 64;

/// One bit per sample of a tile: the samples still to be traced. Only the words a tile of
/// `n` samples uses are cleared.
struct SampleBits {
    uint64_t w[rtt_max_tile_samples / 64];
    explicit SampleBits(int n) {
        for (int i = 0; i < (n + 63) / 64; ++i) w[i] = 0;
    }
    void set(int s) { w[s >> 6] |= uint64_t(1) << (s & 63); }
    bool test(int s) const { return (w[s >> 6] >> (s & 63)) & 1u; }
};

/// The corner rays of a tile (corner_sample order) and their sample indices.
inline auto corners_of(const RayTile& tile, Ray (&corners)[4], int (&cs)[4]) -> const Ray (&)[4] {
    for (int i = 0; i < 4; ++i)
        corners[i] = tile.rays[cs[i] = corner_sample(tile.width, tile.height, i)];
    return corners;
}
inline auto corners_of(const SegmentTile& tile, Ray (&corners)[4], int (&cs)[4]) -> const
    Ray (&)[4] {
    for (int i = 0; i < 4; ++i)
        corners[i] =
            shadow_ray(tile.light, tile.points[cs[i] = corner_sample(tile.width, tile.height, i)]);
    return corners;
}

/// Calls run(active lanes, sample per lane) for each packet-shaped block of the tile holding
/// samples marked in `need`, after stage(lane, sample) filled the packet's lanes.
template <int FK, typename Stage, typename Run>
void for_each_needed_block(int width, int height, const SampleBits& need, RayPacket<FK>& packet,
                           Stage&& stage, Run&& run) {
    constexpr int pw = packet_width<FK>, ph = packet_height<FK>;
    int sample[FK];
    for (int y0 = 0; y0 < height; y0 += ph)
        for (int x0 = 0; x0 < width; x0 += pw) {
            uint32_t active = 0;
            for (int ly = 0; ly < ph; ++ly)
                for (int lx = 0; lx < pw; ++lx) {
                    const int lane = ly * pw + lx, x = x0 + lx, y = y0 + ly;
                    sample[lane] = -1;
                    if (x >= width || y >= height || !need.test(y * width + x)) continue;
                    sample[lane] = y * width + x;
                    active |= 1u << lane;
                    stage(lane, sample[lane]);
                }
            if (!active) continue;
            const int donor = std::countr_zero(active);
            for (uint32_t b = ~active & all_lanes<FK>; b; b &= b - 1)
                packet.set(std::countr_zero(b), packet.get(donor));
            run(active, sample);
        }
}

/// A plane seen from an apex: unit normal n oriented so the apex is on the positive side, at
/// distance h > 0.
struct FacingPlane {
    Vec3f n;
    float h = 0.f;
};

/// Unit normals of the scene's planes (per plane id, from the representative triangle, in
/// double), so a tile orients its end plane with one dot product.
class PlaneNormals {
public:
    PlaneNormals(const std::vector<TriangleVerts>& triangles, const PlaneIds& planes) {
        normals_.reserve(planes.representative.size());
        for (const uint32_t r : planes.representative) {
            const TriangleVerts& t = triangles[r];
            const double e1[3] = {double(t.v1.x) - t.v0.x, double(t.v1.y) - t.v0.y,
                                  double(t.v1.z) - t.v0.z};
            const double e2[3] = {double(t.v2.x) - t.v0.x, double(t.v2.y) - t.v0.y,
                                  double(t.v2.z) - t.v0.z};
            Normal n{{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                      e1[0] * e2[1] - e1[1] * e2[0]},
                     t.v0};
            const double len = std::sqrt(n.n[0] * n.n[0] + n.n[1] * n.n[1] + n.n[2] * n.n[2]);
            for (double& c : n.n) c /= len;
            normals_.push_back(n);
        }
    }
    /// Plane `id` seen from `apex`; false when the apex lies on it (to double rounding).
    bool facing(uint32_t id, const Vec3f& apex, FacingPlane& out) const {
        const Normal& p = normals_[id];
        const double h = p.n[0] * (double(apex.x) - p.at.x) + p.n[1] * (double(apex.y) - p.at.y) +
                         p.n[2] * (double(apex.z) - p.at.z);
        const double s = h < 0.0 ? -1.0 : 1.0;
        out.n = Vec3f(float(p.n[0] * s), float(p.n[1] * s), float(p.n[2] * s));
        out.h = float(std::fabs(h));
        return out.h > 0.f && std::isfinite(out.h);
    }

private:
    struct Normal {
        double n[3];
        Vec3f at;
    };
    std::vector<Normal> normals_;
};

}  // namespace rtt
