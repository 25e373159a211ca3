// The limit kernel of rtt bench answers (answer_limit.h).
#include "experiments/answer_limit.h"

#include <vector>

#include "core/check.h"
#include "geom/camera_simd.h"
#include "geom/triangle_simd.h"
#include "rtt/camera.h"
#include "simd/simd.h"

namespace rtt {
inline namespace RTT_ISA_NS {

int answer_limit_kernel(int count, int rounds, std::span<Hit> hits) {
    constexpr int K = simd_max_width, side = 16;
    RTT_CHECK_EQ(hits.size(), size_t(side * side));
    const CameraRays camera({{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 40}, 1024, 768, 1);
    const CameraTile tile = camera.tile(100, 80);
    std::vector<float> columns(side);
    column_factors(tile, side, columns.data());
    std::vector<TriangleVerts> tris;
    for (int i = 0; i < count; ++i) {  // large triangles in front of the tile, farthest first
        const float z = -10.f + float(i);
        tris.push_back({{-50, -50, z}, {50, -50, z}, {0, 50, z}});
    }
    const int blocks = side * side / K;
    for (int round = 0; round < rounds; ++round)
        for (int blk = 0; blk < blocks; ++blk) {
            const int base = blk * K, row = base / side, col = base % side;
            const Vec3v<K> dir = camera_directions<K>(
                camera.frame(), vfloat<K>::loadu(&columns[size_t(col)]), row_factor(tile, row));
            const WatertightPacket<K> wp(Vec3v<K>(camera.origin()), dir, vfloat<K>(0.f),
                                         vfloat<K>(pos_inf), vbool<K>(true));
            PacketHit<K> best;
            for (int j = 0; j < count; ++j) {
                vfloat<K> t(0.f);  // written where a lane hits
                const vbool<K> hit =
                    intersect_watertight<K>(wp, vbool<K>(true), tris[size_t(j)], t);
                best.update(hit, t, uint32_t(j));
            }
            storeu_pairs(reinterpret_cast<float*>(hits.data() + base), best.t, as_float(best.tri));
        }
    return K;
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
