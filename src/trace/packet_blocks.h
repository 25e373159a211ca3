// Tiles cut into packet-shaped blocks of samples for the packet tracer (trace_packet.h): the
// packet tracers' whole tiles and the samples RTT leaves to them.
#pragma once

#include <bit>
#include <cstdint>
#include <type_traits>

#include "simd/simd.h"
#include "simd/varying.h"
#include "trace/trace_packet.h"

namespace rtt {

/// True when every packet-shaped block of a width x height grid is K consecutive samples (the
/// grid is one block wide, e.g. a 4x4 tile in 16-wide packets) and none is cut by the grid's
/// end: load_packet can read them in registers.
template <int K>
inline bool blocks_are_runs(int width, int height) {
    return width == packet_width<K> && height % packet_height<K> == 0;
}

/// Calls fn(packet, active lane bits, sample index per lane) for each packet-shaped block of a
/// width x height grid; `fill(packet, lane, sample)` stages a sample, `wanted(sample)` says
/// whether it takes part. Inactive lanes are filled with a copy of an active sample.
///
/// Blocks are staged one ahead of the one traced: staging writes lanes with scalar stores, and
/// loading them back as vectors right away fails store forwarding. That stall was ~70 % of
/// trace_packet<4>'s own samples (perf, room 640x480, before this order).
template <int K, typename Wanted, typename Fill, typename Fn>
void for_each_block(int width, int height, Wanted&& wanted, Fill&& fill, Fn&& fn) {
    constexpr int pw = packet_width<K>, ph = packet_height<K>;
    struct Staged {
        RayPacket<K> packet;
        uint32_t active = 0;
        int sample[K];
    };
    Staged staged[2];
    int next = 0;          // buffer the next block is staged in
    bool pending = false;  // staged[next ^ 1] holds a block not traced yet
    for (int y0 = 0; y0 < height; y0 += ph) {
        for (int x0 = 0; x0 < width; x0 += pw) {
            Staged& b = staged[next];
            b.active = 0;
            for (int ly = 0; ly < ph; ++ly) {
                for (int lx = 0; lx < pw; ++lx) {
                    const int lane = ly * pw + lx, x = x0 + lx, y = y0 + ly;
                    b.sample[lane] = -1;
                    if (x >= width || y >= height) continue;
                    const int s = y * width + x;
                    if (!wanted(s)) continue;
                    b.sample[lane] = s;
                    b.active |= 1u << lane;
                    fill(b.packet, lane, s);
                }
            }
            if (!b.active) continue;
            const int donor = std::countr_zero(b.active);
            for (uint32_t m = ~b.active & all_lanes<K>; m; m &= m - 1)
                b.packet.set(std::countr_zero(m), b.packet.get(donor));
            if (pending) {
                const Staged& p = staged[next ^ 1];
                fn(p.packet, p.active, p.sample);
            }
            pending = true;
            next ^= 1;
        }
    }
    if (pending) {
        const Staged& p = staged[next ^ 1];
        fn(p.packet, p.active, p.sample);
    }
}

/// Stores the fields of a packet held in registers (org xyz, dir xyz, tmin, tmax) as vectors,
/// which the traversal's vector loads forward without a stall (staging lane by lane with scalar
/// stores made them wait, and a tile of one block cannot stage ahead). Lanes outside `active`
/// get the first active lane's ray: finite, as the packet tracers ask.
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

/// The packet of K consecutive rays, read in registers (load_records8: 8 floats per ray).
template <int K>
RTT_FORCEINLINE void load_packet(const Ray* run, uint32_t active, RayPacket<K>& packet) {
    static_assert(sizeof(Ray) == 8 * sizeof(float) && std::is_standard_layout_v<Ray>);
    vfloat<K> f[8];
    load_records8(reinterpret_cast<const float*>(run), f);
    store_packet<K>(f, active, packet);
}

/// The packet of the shadow segments shadow_ray(light, p) of K consecutive points, as
/// load_packet (the same float operations as shadow_ray: dir = p - L per component).
template <int K>
RTT_FORCEINLINE void load_segment_packet(const Vec3f& light, const Vec3f* points, uint32_t active,
                                         RayPacket<K>& packet) {
    static_assert(sizeof(Vec3f) == 3 * sizeof(float) && std::is_standard_layout_v<Vec3f>);
    using vf = vfloat<K>;
    vf p[3];
    load_records3(reinterpret_cast<const float*>(points), p);
    vf f[8] = {
        vf(light.x),        vf(light.y),        vf(light.z),        p[0] - vf(light.x),
        p[1] - vf(light.y), p[2] - vf(light.z), vf(shadow_epsilon), vf(1.f - shadow_epsilon)};
    store_packet<K>(f, active, packet);
}

/// for_each_block, except that when the grid's blocks are runs of K consecutive samples
/// (blocks_are_runs) each is read in registers by `load_run(packet, base, active)` instead of
/// lane by lane by `fill`.
template <int K, typename Wanted, typename LoadRun, typename Fill, typename Fn>
void for_each_block_or_run(int width, int height, Wanted&& wanted, LoadRun&& load_run, Fill&& fill,
                           Fn&& fn) {
    if (!blocks_are_runs<K>(width, height)) {
        for_each_block<K>(width, height, wanted, fill, fn);
        return;
    }
    RayPacket<K> packet;
    int sample[K];
    for (int base = 0; base < width * height; base += K) {
        uint32_t active = 0;
        for (int lane = 0; lane < K; ++lane) {
            sample[lane] = base + lane;
            if (wanted(base + lane)) active |= 1u << lane;
        }
        if (!active) continue;
        load_run(packet, base, active);
        fn(packet, active, sample);
    }
}

/// for_each_block over a tile's own rays (runs read by load_packet).
template <int K, typename Wanted, typename Fn>
void for_each_ray_block(const RayTile& tile, Wanted&& wanted, Fn&& fn) {
    for_each_block_or_run<K>(
        tile.width, tile.height, wanted,
        [&](RayPacket<K>& packet, int base, uint32_t active) {
            load_packet<K>(tile.rays.data() + base, active, packet);
        },
        [&](RayPacket<K>& packet, int lane, int s) { packet.set(lane, tile.rays[s]); }, fn);
}

/// The same over a shadow tile's segments shadow_ray(tile.light, point).
template <int K, typename Wanted, typename Fn>
void for_each_segment_block(const SegmentTile& tile, Wanted&& wanted, Fn&& fn) {
    for_each_block_or_run<K>(
        tile.width, tile.height, wanted,
        [&](RayPacket<K>& packet, int base, uint32_t active) {
            load_segment_packet<K>(tile.light, tile.points.data() + base, active, packet);
        },
        [&](RayPacket<K>& packet, int lane, int s) {
            packet.set(lane, shadow_ray(tile.light, tile.points[s]));
        },
        fn);
}

}  // namespace rtt
