// Tiles cut into packet-shaped blocks of samples for the packet tracer (trace_packet.h): the
// packet tracers' whole tiles and the samples RTT leaves to them.
#pragma once

#include <bit>
#include <cstdint>

#include "simd/varying.h"
#include "trace/trace_packet.h"

namespace rtt {

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

}  // namespace rtt
