// A tile's relevant list (the triangles its rays can hit, Dmitriev, Havran, Seidel 2004, section
// 3) and the mailbox that keeps a triangle referenced by several leaves from being tested twice
// while the list is built.
#pragma once

#include <algorithm>
#include <cstdint>
#include <iterator>

#include "simd/isa.h"

namespace rtt {
inline namespace RTT_ISA_NS {

/// Capacity of a tile's relevant list; a longer list ends RTT for the tile (it would not pay).
inline constexpr int rtt_max_relevant = 64;

struct RelevantList {
    int count = 0;
    uint32_t tri[rtt_max_relevant];
    float min_offset[rtt_max_relevant];  ///< CornerVerdict::min_offset of each entry.
};

/// Marks triangles already tested in the current tile (a triangle can sit in several leaves):
/// a small open-addressing hash set that stays in L1 (a tile meets tens of triangles, not a
/// per-scene array touched at random), cleared per tile by a stamp. When it fills up, further
/// triangles are reported unseen: they are tested again (harmless) and may repeat in the list.
class TriangleMailbox {
public:
    /// Starts a new tile.
    void begin(size_t /*triangle_count*/) {
        if (++stamp_ == 0) {
            std::fill(std::begin(stamps_), std::end(stamps_), 0u);
            stamp_ = 1;
        }
        used_ = 0;
    }
    /// True when `id` was already seen in this tile; marks it seen.
    bool seen(uint32_t id) {
        uint32_t slot = (id * 2654435761u) >> (32 - bits);
        for (;; slot = (slot + 1) & (size - 1)) {
            if (stamps_[slot] != stamp_) {
                if (used_ == size * 3 / 4) return false;
                stamps_[slot] = stamp_;
                ids_[slot] = id;
                ++used_;
                return false;
            }
            if (ids_[slot] == id) return true;
        }
    }

private:
    static constexpr int bits = 9;
    static constexpr uint32_t size = 1u << bits;
    uint32_t stamps_[size] = {};
    uint32_t ids_[size];
    uint32_t stamp_ = 0;
    uint32_t used_ = 0;
};

}  // namespace RTT_ISA_NS
}  // namespace rtt
