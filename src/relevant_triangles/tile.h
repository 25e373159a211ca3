// Tile-level helpers of the RTT tracer (primary_tiles.cpp): which samples still need tracing, the
// corner rays of a tile, and the plane a shaft's rays end on.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "geom/plane_id.h"
#include "relevant_triangles/region.h"
#include "rtt/rtt_options.h"
#include "rtt/tracer.h"
#include "simd/isa.h"
#include "trace/trace_packet.h"

namespace rtt {
inline namespace RTT_ISA_NS {

/// Largest tile RTT takes on: 4x4 pixels with 16 x 16 antialiasing.
inline constexpr int rtt_max_tile_samples = rtt_max_samples_per_tile;

/// One bit per sample of a tile: the samples still to be traced. Only the words a tile of
/// `n` samples uses are cleared.
struct SampleBits {
    uint64_t w[rtt_max_tile_samples / 64];
    explicit SampleBits(int n) {
        for (int i = 0; i < (n + 63) / 64; ++i) w[i] = 0;
    }
    void set(int s) { w[s >> 6] |= uint64_t(1) << (s & 63); }
    /// Sets samples base + i for the bits i of `lanes` (base a multiple of the lane count, so
    /// they share one word).
    void set_lanes(int base, uint32_t lanes) { w[base >> 6] |= uint64_t(lanes) << (base & 63); }
    bool test(int s) const { return (w[s >> 6] >> (s & 63)) & 1u; }
    /// True when none of the first n samples is set.
    bool none(int n) const {
        uint64_t any = 0;
        for (int i = 0; i < (n + 63) / 64; ++i) any |= w[i];
        return any == 0;
    }
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
    PlaneNormals(std::span<const TriangleVerts> triangles, const PlaneIds& planes) {
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

}  // namespace RTT_ISA_NS
}  // namespace rtt
