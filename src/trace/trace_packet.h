// SIMD packet tracing through the kd-tree (Wald, Benthin, Wagner, Slusallek 2001, "Interactive
// Rendering with Coherent Ray Tracing"): K rays share one traversal, one stack and one
// triangle test per leaf triangle, with an active-lane mask. The paper's baseline is K = 4
// (SSE); K = 8 (AVX2) and K = 16 (AVX-512) are built when the compiler targets them.
//
// Per lane, the traversal follows the semantics documented in trace_ray.h (margins on split
// distances, padded root box, NaN rule, inclusive best.t, skip of popped nodes starting after
// the lane's best t), and leaves use the K-wide watertight test of triangle_simd.h, which is the
// scalar test lane by lane. Every lane therefore returns the brute-force answer, as trace_ray
// does. Packets whose direction signs differ on some axis are split by octant into
// sub-packets (a lone ray goes through trace_ray).
#pragma once

#include <cstdint>
#include <span>

#include "geom/triangle.h"
#include "rtt/kdtree.h"
#include "rtt/math.h"
#include "rtt/tracer.h"
#include "simd/isa.h"
#include "trace/blocker_cache.h"

namespace rtt {
inline namespace RTT_ISA_NS {

/// Shape of the block of tile samples one packet covers: 2x2 for K = 4 (the paper's
/// baseline), 4x2 for K = 8, 4x4 for K = 16. Lane = row * packet_width + column.
template <int K>
inline constexpr int packet_width = K == 4 ? 2 : 4;
template <int K>
inline constexpr int packet_height = K / packet_width<K>;

/// K rays staged as structure of arrays (lane i = ray i), the input of trace_packet.
/// 64-byte aligned so every row loads as aligned vectors at every width.
template <int K>
struct alignas(64) RayPacket {
    alignas(64) float org[3][K];
    alignas(64) float dir[3][K];
    alignas(64) float tmin[K];
    alignas(64) float tmax[K];

    void set(int lane, const Ray& r) {
        for (int a = 0; a < 3; ++a) {
            org[a][lane] = r.org[a];
            dir[a][lane] = r.dir[a];
        }
        tmin[lane] = r.tmin;
        tmax[lane] = r.tmax;
    }
    Ray get(int lane) const {
        return Ray{{org[0][lane], org[1][lane], org[2][lane]},
                   {dir[0][lane], dir[1][lane], dir[2][lane]},
                   tmin[lane],
                   tmax[lane]};
    }
};
// Each of the four arrays starts a cache line: 4 lines (256 bytes) at K = 4, 8 at K = 16.
static_assert(sizeof(RayPacket<4>) == 256 && sizeof(RayPacket<16>) == 512);

/// Work done by packet traversals, summed over calls (collected only when asked for: the
/// counting code is compiled into a separate instantiation of the traversal).
struct PacketStats {
    uint64_t packets = 0;      ///< Packet traversals (one per octant group of 2+ lanes).
    uint64_t lanes = 0;        ///< Lanes those traversals started with.
    uint64_t single_rays = 0;  ///< Lanes alone in their octant, traced by trace_ray.
    uint64_t inner = 0;        ///< Inner nodes visited by packets.
    uint64_t inner_lanes = 0;  ///< Active lanes summed over those visits (= scalar node visits).
    uint64_t leaves = 0;       ///< Leaves visited by packets.
    uint64_t tests = 0;        ///< K-wide triangle tests.
    uint64_t test_lanes = 0;   ///< Active lanes summed over those tests.
    uint64_t cached = 0;       ///< Lanes a BlockerCache triangle blocked before traversal.

    PacketStats& operator+=(const PacketStats& o);
};

/// Closest hit of each ray of `rays` whose bit is set in `active` (bit i = lane i):
/// hits[i] == trace_ray(tree, triangles, rays.get(i)). Other entries of `hits` are untouched.
/// Inactive lanes are ignored but should hold finite rays (a copy of an active one).
template <int K>
void trace_packet(const KdTree& tree, std::span<const TriangleVerts> triangles,
                  const RayPacket<K>& rays, uint32_t active, Hit* hits,
                  PacketStats* stats = nullptr);

/// Lane bits of the active rays that meet a triangle within [tmin, tmax]:
/// bit i == occluded_ray(tree, triangles, rays.get(i)) for i in `active`.
/// With `blockers`, its triangles are tested first and the triangle that blocks a lane in the
/// traversal is noted in it.
template <int K>
uint32_t occluded_packet(const KdTree& tree, std::span<const TriangleVerts> triangles,
                         const RayPacket<K>& rays, uint32_t active, PacketStats* stats = nullptr,
                         BlockerCache* blockers = nullptr);

/// Closest hits of a whole tile, in packets of packet_width<K> x packet_height<K> samples
/// (lanes past the tile's border are inactive). hits.size() == tile.rays.size().
template <int K>
void trace_tile_packets(const KdTree& tree, std::span<const TriangleVerts> triangles,
                        const RayTile& tile, std::span<Hit> hits, PacketStats* stats = nullptr);

/// Visibility of a tile's active shadow segments (shadow_ray(tile.light, point)), in packets
/// as above: visible[i] = 1 when unoccluded, 0 when occluded or inactive. Returns the number
/// of active segments. `blockers` as in occluded_packet, carried from packet to packet.
template <int K>
uint64_t occluded_tile_packets(const KdTree& tree, std::span<const TriangleVerts> triangles,
                               const SegmentTile& tile, std::span<uint8_t> visible,
                               PacketStats* stats = nullptr, BlockerCache* blockers = nullptr);

}  // namespace RTT_ISA_NS
}  // namespace rtt
