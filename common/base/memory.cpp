// glibc's malloc tuning (mallopt): see memory.h for why.
#include "common/base/memory.h"

#include <cstdlib>  // defines __GLIBC__ with glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace pathfarm {

bool keep_freed_memory() {
#if defined(__GLIBC__)
    // The largest mmap threshold glibc accepts on 64-bit (DEFAULT_MMAP_THRESHOLD_MAX): blocks
    // up to 32 MiB (a 1920x1080 RGB float image is 24 MiB) come from the heap. Setting it also
    // stops glibc's own threshold adjustment, which maps a block again whenever it is exactly
    // as large as the last one freed: a frame loop's case.
    constexpr int kMmapThreshold = 32 << 20;
    // Free memory at the top of a heap is returned to the system only beyond this.
    constexpr int kTrimThreshold = 1 << 30;
    return mallopt(M_MMAP_THRESHOLD, kMmapThreshold) == 1 &&
           mallopt(M_TRIM_THRESHOLD, kTrimThreshold) == 1;
#else
    return false;
#endif
}

}  // namespace pathfarm
