// Split-candidate events of the Wald–Havran kd-tree build ("On building fast kd-trees for ray
// tracing, and on doing that in O(N log N)", 2006, section 4).
//
// Each triangle of a node contributes, per axis, the bounds of its part inside the node (see
// kd_clip.h): a `start` and an `end` event, or one `planar` event when those bounds are flat.
// Every event list is kept sorted by (position, type, triangle) with end < planar < start, the
// order the SAH sweep needs; the triangle index only makes the order total, so the build is
// deterministic whatever sorting algorithm or thread count produced it.
#pragma once

#include <cstdint>
#include <vector>

#include "core/large_arrays.h"
#include "rtt/math.h"

namespace rtt::kd {

enum class EventType : uint32_t { end = 0, planar = 1, start = 2 };

/// 8 bytes: position, then type (2 bits) and triangle index (30 bits) packed into one key.
struct Event {
    float pos;
    uint32_t key;

    static constexpr uint32_t tri_mask = (1u << 30) - 1;

    Event(float p, EventType type, uint32_t tri) : pos(p + 0.f), key(uint32_t(type) << 30 | tri) {}
    uint32_t tri() const { return key & tri_mask; }
    EventType type() const { return EventType(key >> 30); }
    bool operator<(const Event& o) const { return pos < o.pos || (pos == o.pos && key < o.key); }
};
static_assert(sizeof(Event) == 8);

using EventList = std::vector<Event>;

/// A triangle of a node with the bounds of its part inside the node: what every node of the
/// build holds; events are made from these only where a sweep needs them.
struct TriBox {
    Bbox3f box;
    uint32_t tri;
};
/// The build's lists of them, on huge pages where they are large (core/large_arrays.h).
using TriBoxes = large_vector<TriBox>;

}  // namespace rtt::kd
