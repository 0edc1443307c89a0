// Process-wide memory setup for the long-running processes (coordinator, tracer daemon).
#pragma once

#include <cstddef>
#include <memory>

namespace pathfarm {

// Keeps freed memory in the process for reuse instead of returning it to the system. A frame
// loop allocates buffers of the same sizes every frame (images, first hits, G-buffers); by
// default glibc maps each of them afresh (blocks above its mmap threshold) and hands them back
// when freed, so every frame pays a page fault per page touched, which on virtual machines
// costs microseconds each (docs/denoise.md, "Page faults and threads"). After this call such
// blocks come from the heap and stay there; the process keeps its peak footprint. False if
// the C library refused (or is not glibc): nothing changed.
bool keep_freed_memory();

// keep_freed_memory(), and the main heap grown at once by `reserve` bytes of address space
// advised as transparent huge pages (what glibc's glibc.malloc.hugetlb=1 tunable does, which
// can only be set in the environment before start). For a process that allocates its large
// buffers once and touches each page once (pathfarm-render: the image, first hits, G-buffer
// and the denoiser's planes): 2 MiB faults instead of 4 KiB ones, on this machine the
// difference between about 120 and 20 ms for a 640x360 frame's denoising. Only the main
// thread's heap (other threads' allocations come from arenas of their own), and only
// `reserve` bytes of it; untouched reserve costs no memory. False, and nothing but
// keep_freed_memory() done, where the heap did not grow (another malloc, such as a
// sanitizer's, or no huge pages on the system).
bool back_main_heap_with_huge_pages(std::size_t reserve);

// Zeroed memory for a large working set read all over at once (the wavelet's planes): aligned
// to 2 MiB and advised as transparent huge pages (Linux's "madvise" mode, Debian's default),
// so a fresh process faults it in 2 MiB at a time instead of 4 KiB (one fault instead of 512,
// each several microseconds on a virtual machine), and a tap's reads across many rows and
// planes need fewer TLB entries. Where the kernel gives no huge pages it is ordinary memory.
class HugePageBuffer {
public:
    HugePageBuffer() = default;
    explicit HugePageBuffer(std::size_t bytes);
    void* data() const { return data_.get(); }
    std::size_t size() const { return bytes_; }

private:
    struct Free {
        void operator()(void* p) const;
    };
    std::unique_ptr<void, Free> data_;
    std::size_t bytes_ = 0;
};

}  // namespace pathfarm
