// The 8-byte kd-tree node (Wald's / pbrt's layout).
#pragma once

#include <cstdint>
#include <cstring>

namespace rtt {

/// Inner node: `split` position, axis in the low 2 bits of `bits`, index of the above
/// (right, greater-coordinate) child in the upper 30 bits; the below child is node + 1.
/// Leaf: low 2 bits = 3, triangle count in the upper 30 bits, and `first` indexes the
/// tree's leaf triangle list.
struct alignas(8) KdNode {
    union {
        float split;
        uint32_t first;
    };
    uint32_t bits;

    static constexpr uint32_t max_index = (1u << 30) - 1;

    bool is_leaf() const { return (bits & 3u) == 3u; }
    int axis() const { return int(bits & 3u); }
    uint32_t above_child() const { return bits >> 2; }
    uint32_t triangle_count() const { return bits >> 2; }
    uint32_t first_triangle() const { return first; }

    /// Encoders return false when a value does not fit its field.
    bool set_inner(int axis_, float split_, uint32_t above) {
        if (above > max_index || axis_ < 0 || axis_ > 2) return false;
        split = split_;
        bits = (above << 2) | uint32_t(axis_);
        return true;
    }
    bool set_leaf(uint32_t first_, uint32_t count) {
        if (count > max_index) return false;
        first = first_;
        bits = (count << 2) | 3u;
        return true;
    }
};
static_assert(sizeof(KdNode) == 8, "a kd-tree node is 8 bytes; eight fit in a cache line");

}  // namespace rtt
