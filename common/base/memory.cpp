// glibc's malloc tuning (mallopt): see memory.h for why.
#include "common/base/memory.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>  // defines __GLIBC__ with glibc
#include <cstring>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace pathfarm {

namespace {

constexpr std::size_t kHugePage = std::size_t(2) << 20;
// The largest mmap threshold glibc accepts on 64-bit (DEFAULT_MMAP_THRESHOLD_MAX): blocks up to
// 32 MiB (a 1920x1080 RGB float image is 24 MiB) come from the heap.
constexpr std::size_t kMmapThreshold = std::size_t(32) << 20;

}  // namespace

bool keep_freed_memory() {
#if defined(__GLIBC__)
    // Setting the threshold also stops glibc's own adjustment of it, which maps a block again
    // whenever it is exactly as large as the last one freed: a frame loop's case.
    // Free memory at the top of a heap is returned to the system only beyond 1 GiB.
    constexpr int kTrimThreshold = 1 << 30;
    return mallopt(M_MMAP_THRESHOLD, int(kMmapThreshold)) == 1 &&
           mallopt(M_TRIM_THRESHOLD, kTrimThreshold) == 1;
#else
    return false;
#endif
}

bool back_main_heap_with_huge_pages(std::size_t reserve) {
    if (!keep_freed_memory()) return false;
#if defined(__GLIBC__) && defined(__linux__) && defined(MADV_HUGEPAGE)
    if (reserve > std::size_t(1) << 30 || mallopt(M_TOP_PAD, int(reserve)) != 1) return false;
    const auto brk_now = [] { return reinterpret_cast<std::uintptr_t>(sbrk(0)); };
    const std::uintptr_t before = brk_now();
    // A request beyond the heap's free top (below the break) grows it by the request plus the
    // pad (M_TOP_PAD), now, from this thread; under the mmap threshold, so from the heap.
    const std::size_t free_top = mallinfo2().keepcost;
    void* probe = std::malloc(std::min(free_top + kHugePage, kMmapThreshold - kHugePage));
    asm volatile("" : : "r"(probe) : "memory");  // a used block: malloc and free not elided
    const std::uintptr_t after = brk_now();
    std::free(probe);               // stays in the heap: keep_freed_memory's trim threshold
    mallopt(M_TOP_PAD, 128 << 10);  // glibc's default again (mallopt(3)) for later growth
    if (before == std::uintptr_t(-1) || after < before || free_top > before) return false;
    // From the free top's start (what was free before the growth is advised too).
    const std::uintptr_t first = (before - free_top + kHugePage - 1) / kHugePage * kHugePage;
    const std::uintptr_t last = after / kHugePage * kHugePage;
    if (last <= first) return false;
    return madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE) == 0;
#else
    return false;
#endif
}

HugePageBuffer::HugePageBuffer(std::size_t bytes) : bytes_(bytes) {
    if (bytes == 0) return;
    // Whole huge pages: aligned_alloc wants a multiple of the alignment, and a last partial
    // page would be an ordinary one.
    const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    data_.reset(std::aligned_alloc(kHugePage, rounded));
    if (!data_) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    // Advice only: refused (THP "never", an old kernel) it leaves 4 KiB pages.
    (void)madvise(data_.get(), rounded, MADV_HUGEPAGE);
#endif
    std::memset(data_.get(), 0, bytes);  // faults the pages in, huge where granted
}

void HugePageBuffer::Free::operator()(void* p) const { std::free(p); }

}  // namespace pathfarm
