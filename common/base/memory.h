// Process-wide memory setup for the long-running processes (coordinator, tracer daemon).
#pragma once

namespace pathfarm {

// Keeps freed memory in the process for reuse instead of returning it to the system. A frame
// loop allocates buffers of the same sizes every frame (images, first hits, G-buffers); by
// default glibc maps each of them afresh (blocks above its mmap threshold) and hands them back
// when freed, so every frame pays a page fault per page touched, which on virtual machines
// costs microseconds each (docs/denoise.md, "Page faults and threads"). After this call such
// blocks come from the heap and stay there; the process keeps its peak footprint. False if
// the C library refused (or is not glibc): nothing changed.
bool keep_freed_memory();

}  // namespace pathfarm
