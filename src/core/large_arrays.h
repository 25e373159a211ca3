// Large arrays on transparent huge pages: a build writes hundreds of MB of fresh memory, and on
// 4 KiB pages the kernel's page faults were a quarter to a half of a first build
// (docs/benchmarks.md, "Arbitrary rays"). Where the system offers huge pages on request (Linux,
// transparent_hugepage "madvise" or "always"), one 2 MiB page faults where 512 small ones did.
#pragma once

#include <cstddef>
#include <vector>

namespace rtt {

/// `bytes` aligned to `align`: arrays of at least large_array_bytes are 2 MiB-aligned, rounded
/// up to whole 2 MiB pages and advised as huge pages; smaller ones come from operator new.
/// Throws std::bad_alloc.
void* allocate_large(std::size_t bytes, std::size_t align);
/// Frees what allocate_large(bytes, align) returned.
void free_large(void* p, std::size_t bytes, std::size_t align) noexcept;

inline constexpr std::size_t large_array_bytes = std::size_t(4) << 20;

/// A std::allocator for the arrays builds fill: allocate_large underneath.
template <typename T>
struct LargeArrayAllocator {
    using value_type = T;
    LargeArrayAllocator() = default;
    template <typename U>
    LargeArrayAllocator(const LargeArrayAllocator<U>&) noexcept {}
    T* allocate(std::size_t n) {
        return static_cast<T*>(allocate_large(n * sizeof(T), alignof(T)));
    }
    void deallocate(T* p, std::size_t n) noexcept { free_large(p, n * sizeof(T), alignof(T)); }
    template <typename U>
    bool operator==(const LargeArrayAllocator<U>&) const noexcept {
        return true;
    }
};

template <typename T>
using large_vector = std::vector<T, LargeArrayAllocator<T>>;

}  // namespace rtt
