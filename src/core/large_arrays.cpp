#include "core/large_arrays.h"

#include <cstdlib>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace rtt {
namespace {

constexpr std::size_t huge_page = std::size_t(2) << 20;

std::size_t whole_pages(std::size_t bytes) {
    return (bytes + huge_page - 1) / huge_page * huge_page;
}

}  // namespace

void* allocate_large(std::size_t bytes, std::size_t align) {
    if (bytes < large_array_bytes) return ::operator new(bytes, std::align_val_t(align));
    void* p = std::aligned_alloc(huge_page, whole_pages(bytes));
    if (!p) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    // Advice only: where huge pages are off or exhausted the pages stay small.
    madvise(p, whole_pages(bytes), MADV_HUGEPAGE);
#endif
    return p;
}

void free_large(void* p, std::size_t bytes, std::size_t align) noexcept {
    if (bytes < large_array_bytes)
        ::operator delete(p, std::align_val_t(align));
    else
        std::free(p);
}

}  // namespace rtt
