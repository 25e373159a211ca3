// Tiles cut into packet-shaped blocks of samples for the packet tracer (trace_packet.h): the
// packet tracers' whole tiles and the samples RTT leaves to them.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "core/platform.h"
#include "simd/isa.h"
#include "simd/simd.h"
#include "simd/varying.h"
#include "trace/trace_packet.h"

namespace rtt {
inline namespace RTT_ISA_NS {

/// Stores the fields of a packet held in registers (org xyz, dir xyz, tmin, tmax) as vectors,
/// which the traversal's vector loads forward without a stall (scalar stores lane by lane make
/// them wait). Lanes outside `active` get the first active lane's ray: finite, as the packet
/// tracers ask.
template <int K>
RTT_FORCEINLINE void store_packet(vfloat<K> (&f)[8], uint32_t active, RayPacket<K>& packet) {
    if (active != all_lanes<K>) {
        const vbool<K> keep = vbool<K>::from_bits(active);
        const int donor = std::countr_zero(active);
        for (vfloat<K>& v : f) v = select(keep, v, vfloat<K>(v[donor]));
    }
    for (int a = 0; a < 3; ++a) {
        store(packet.org[a], f[a]);
        store(packet.dir[a], f[3 + a]);
    }
    store(packet.tmin, f[6]);
    store(packet.tmax, f[7]);
}

/// The packet of a block of rays, read in registers: packet_height<K> rows of packet_width<K>
/// consecutive rays, `stride` rays apart (load_record_rows8: 8 floats per ray).
template <int K>
RTT_FORCEINLINE void load_packet(const Ray* first, int stride, uint32_t active,
                                 RayPacket<K>& packet) {
    static_assert(sizeof(Ray) == 8 * sizeof(float) && std::is_standard_layout_v<Ray>);
    vfloat<K> f[8];
    load_record_rows8(reinterpret_cast<const float*>(first), std::ptrdiff_t(8) * stride, f);
    store_packet<K>(f, active, packet);
}

/// The packet of the shadow segments shadow_ray(light, p) of a block of points laid out as in
/// load_packet (the same float operations as shadow_ray: dir = p - L per component).
template <int K>
RTT_FORCEINLINE void load_segment_packet(const Vec3f& light, const Vec3f* first, int stride,
                                         uint32_t active, RayPacket<K>& packet) {
    static_assert(sizeof(Vec3f) == 3 * sizeof(float) && std::is_standard_layout_v<Vec3f>);
    using vf = vfloat<K>;
    vf p[3];
    load_record_rows3(reinterpret_cast<const float*>(first), std::ptrdiff_t(3) * stride, p);
    vf f[8] = {
        vf(light.x),        vf(light.y),        vf(light.z),        p[0] - vf(light.x),
        p[1] - vf(light.y), p[2] - vf(light.z), vf(shadow_epsilon), vf(1.f - shadow_epsilon)};
    store_packet<K>(f, active, packet);
}

/// Blocks ahead of the one traced whose records are prefetched: a group of two packets
/// (trace_bvh_packets.cpp) takes far longer than a fetch.
inline constexpr int prefetch_blocks_ahead = 2;

/// Starts loading the `rows` rows of `row_bytes` bytes, `stride` bytes apart, from `first`.
RTT_FORCEINLINE void prefetch_rows(const void* first, int rows, size_t row_bytes, size_t stride) {
    for (int r = 0; r < rows; ++r)
        prefetch_bytes(static_cast<const char*>(first) + size_t(r) * stride, row_bytes);
}

/// Calls fn(packet, active lane bits, sample index per lane) for each packet-shaped block of a
/// width x height grid; `wanted(sample)` says whether a sample takes part. A block inside the
/// grid is read in registers by `load_block(packet, first sample, active)`; one cut by the
/// grid's end (sizes that are not multiples of the tile) is staged lane by lane by
/// `fill(packet, lane, sample)`, its inactive lanes filled with a copy of an active sample.
/// `prefetch(first sample)` is called for the block prefetch_blocks_ahead along its row of
/// blocks, when that block lies inside the grid.
template <int K, typename Wanted, typename LoadBlock, typename Fill, typename Prefetch, typename Fn>
void for_each_block(int width, int height, Wanted&& wanted, LoadBlock&& load_block, Fill&& fill,
                    Prefetch&& prefetch, Fn&& fn) {
    constexpr int pw = packet_width<K>, ph = packet_height<K>;
    RayPacket<K> packet;
    int sample[K];
    for (int y0 = 0; y0 < height; y0 += ph) {
        for (int x0 = 0; x0 < width; x0 += pw) {
            if (const int ahead = x0 + prefetch_blocks_ahead * pw;
                ahead + pw <= width && y0 + ph <= height)
                prefetch(y0 * width + ahead);
            uint32_t active = 0;
            for (int ly = 0; ly < ph; ++ly) {
                for (int lx = 0; lx < pw; ++lx) {
                    const int lane = ly * pw + lx, x = x0 + lx, y = y0 + ly;
                    const int s = x < width && y < height ? y * width + x : -1;
                    sample[lane] = s;
                    if (s >= 0 && wanted(s)) active |= 1u << lane;
                }
            }
            if (!active) continue;
            if (x0 + pw <= width && y0 + ph <= height) {
                load_block(packet, y0 * width + x0, active);
            } else {
                const int donor = sample[std::countr_zero(active)];
                for (int lane = 0; lane < K; ++lane)
                    fill(packet, lane, (active >> lane) & 1u ? sample[lane] : donor);
            }
            fn(packet, active, sample);
        }
    }
}

/// for_each_block over a tile's own rays (blocks inside the tile read by load_packet).
template <int K, typename Wanted, typename Fn>
void for_each_ray_block(const RayTile& tile, Wanted&& wanted, Fn&& fn) {
    for_each_block<K>(
        tile.width, tile.height, wanted,
        [&](RayPacket<K>& packet, int first, uint32_t active) {
            load_packet<K>(tile.rays.data() + first, tile.width, active, packet);
        },
        [&](RayPacket<K>& packet, int lane, int s) { packet.set(lane, tile.rays[s]); },
        [&](int first) {
            prefetch_rows(tile.rays.data() + first, packet_height<K>, sizeof(Ray) * packet_width<K>,
                          sizeof(Ray) * size_t(tile.width));
        },
        fn);
}

/// The same over a shadow tile's segments shadow_ray(tile.light, point).
template <int K, typename Wanted, typename Fn>
void for_each_segment_block(const SegmentTile& tile, Wanted&& wanted, Fn&& fn) {
    for_each_block<K>(
        tile.width, tile.height, wanted,
        [&](RayPacket<K>& packet, int first, uint32_t active) {
            load_segment_packet<K>(tile.light, tile.points.data() + first, tile.width, active,
                                   packet);
        },
        [&](RayPacket<K>& packet, int lane, int s) {
            packet.set(lane, shadow_ray(tile.light, tile.points[s]));
        },
        [&](int first) {
            prefetch_rows(tile.points.data() + first, packet_height<K>,
                          sizeof(Vec3f) * packet_width<K>, sizeof(Vec3f) * size_t(tile.width));
        },
        fn);
}

}  // namespace RTT_ISA_NS
}  // namespace rtt
