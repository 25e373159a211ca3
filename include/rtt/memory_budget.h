// Refusing work that cannot fit in memory, before allocating it.
//
// Why not just let the allocation fail: on Linux, with overcommit, a vector that grows past the
// machine's memory is not refused with std::bad_alloc; its pages are touched one by one until
// the kernel's OOM killer ends the process without a message. So every request whose size the
// user controls (image size, samples, triangle count after instancing) is estimated up front and
// refused with a one-line rtt::Error when the estimate exceeds what this process may have.
#pragma once

#include <cstdint>
#include <string>

namespace rtt {

/// Bytes this process may use at most: the smallest of the machine's physical memory, the
/// cgroup memory limit (v2 memory.max or v1 memory.limit_in_bytes) and RLIMIT_AS / RLIMIT_DATA.
uint64_t memory_budget();

/// Throws rtt::Error "<what> needs about X GiB of memory, but at most Y GiB is available
/// (physical memory, cgroup and ulimit)" when `bytes` exceeds memory_budget().
void require_memory(uint64_t bytes, const std::string& what);

/// Estimated peak bytes of a scene with this many vertices and triangles once its kd-tree and a
/// tracer are built: the scene arrays, the gathered triangles, the build's per-node triangle
/// lists and bounds (parent and children alive together), nodes and leaf lists.
uint64_t scene_memory_bytes(uint64_t vertices, uint64_t triangles);

/// a * b + c, saturating at UINT64_MAX instead of wrapping (counts come from files).
uint64_t saturating_mul_add(uint64_t a, uint64_t b, uint64_t c);

}  // namespace rtt
