// keep_freed_memory: a frame loop's buffers, freed and allocated again at the same size, are
// not faulted in again. back_main_heap_with_huge_pages and HugePageBuffer: large buffers
// faulted in 2 MiB at a time where the system has transparent huge pages.
#include "common/base/memory.h"

#include <malloc.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#if defined(__SANITIZE_ADDRESS__)
#define PATHFARM_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PATHFARM_ASAN 1
#endif
#endif

namespace pathfarm {
namespace {

long minor_faults() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_minflt;
}

// Minor page faults of `frames` frames that each allocate, write and free the same 6 MiB
// (about a 640x360 G-buffer), after a first frame that faults it in.
long refaults_per_frame(int frames) {
    constexpr std::size_t kFloats = (6u << 20) / sizeof(float);
    const auto frame = [] {
        std::vector<float> buffer(kFloats, 1.0f);
        volatile float sink = buffer[kFloats / 2];
        (void)sink;
    };
    frame();
    const long before = minor_faults();
    for (int f = 0; f < frames; ++f)
        frame();
    return (minor_faults() - before) / frames;
}

// `measure` run in a child process (the malloc settings are process-wide), its result.
long in_child(const std::function<long()>& measure) {
    int fds[2];
    if (pipe(fds) != 0) return -1;
    const pid_t child = fork();
    if (child < 0) return -1;
    if (child == 0) {
        const long value = measure();
        const bool written = write(fds[1], &value, sizeof value) == ssize_t(sizeof value);
        _exit(written ? 0 : 1);
    }
    long value = -1;
    if (read(fds[0], &value, sizeof value) != ssize_t(sizeof value)) value = -1;
    int status = 0;
    waitpid(child, &status, 0);
    close(fds[0]);
    close(fds[1]);
    return value;
}

// The system's transparent huge page mode: "always", "madvise" or "never" ("" if unknown).
std::string huge_page_mode() {
    std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string modes;
    std::getline(in, modes);
    for (const char* mode : {"always", "madvise", "never"})
        if (modes.find(std::string("[") + mode + "]") != std::string::npos) return mode;
    return "";
}

// Whether madvise(MADV_HUGEPAGE) can give this process huge pages.
bool transparent_huge_pages() {
    const std::string mode = huge_page_mode();
    return mode == "always" || mode == "madvise";
}

// The system's count of faults that wanted a huge page and got 4 KiB ones (no free huge page:
// fragmented or short memory, which no process setting changes).
long huge_page_fallbacks() {
    std::ifstream in("/proc/vmstat");
    std::string name;
    long value = 0;
    while (in >> name >> value)
        if (name == "thp_fault_fallback") return value;
    return 0;
}

// Minor page faults while a zeroed 64 MiB vector (a 640x360 frame's image, first hits, G-buffer
// and denoiser planes) is allocated and written.
long faults_of_a_large_buffer() {
    const long before = minor_faults();
    std::vector<float> buffer((64u << 20) / sizeof(float), 1.0f);
    volatile float sink = buffer[buffer.size() / 2];
    (void)sink;
    return minor_faults() - before;
}

TEST(HugePages, TheMainHeapFaultsInTwoMiBAtATime) {
#if defined(PATHFARM_ASAN)
    GTEST_SKIP() << "AddressSanitizer replaces malloc";
#endif
    // "always" puts the plain heap on huge pages too: nothing to compare.
    if (huge_page_mode() != "madvise") GTEST_SKIP() << "transparent huge pages not in madvise mode";
    const long fallbacks = huge_page_fallbacks();
    const long plain = in_child([] {
        if (!keep_freed_memory()) return -1L;
        return faults_of_a_large_buffer();
    });
    const long huge = in_child([] {
        if (!back_main_heap_with_huge_pages(std::size_t(128) << 20)) return -2L;
        return faults_of_a_large_buffer();
    });
    std::printf("page faults for 64 MiB: %ld on the plain heap, %ld advised\n", plain, huge);
    if (huge_page_fallbacks() > fallbacks) GTEST_SKIP() << "the kernel had no free huge page";
    ASSERT_GE(huge, 0) << "back_main_heap_with_huge_pages refused (-2) or the child failed";
    EXPECT_GT(plain, 4096) << "the plain heap no longer faults 4-16 KiB at a time: this test "
                              "shows nothing";
    // 32 huge pages; before the first 2 MiB boundary up to 512 ordinary ones, and 4 KiB
    // copy-on-write faults where the heap's free top was touched before the fork.
    EXPECT_LT(huge, plain / 8);
}

TEST(HugePages, AHugePageBufferIsZeroedAlignedAndFaultedInWhole) {
    const HugePageBuffer empty;
    EXPECT_EQ(empty.size(), 0u);
    EXPECT_EQ(empty.data(), nullptr);
    const long before = minor_faults(), fallbacks = huge_page_fallbacks();
    const HugePageBuffer buffer((16u << 20) + 12);
    const long faults = minor_faults() - before;
    // Huge pages here, and the kernel had a free one.
    [[maybe_unused]] const bool huge =
        transparent_huge_pages() && huge_page_fallbacks() == fallbacks;
    ASSERT_NE(buffer.data(), nullptr);
    EXPECT_EQ(buffer.size(), (16u << 20) + 12);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(buffer.data()) % (2u << 20), 0u);
    const auto* bytes = static_cast<const unsigned char*>(buffer.data());
    std::size_t nonzero = 0;
    for (std::size_t i = 0; i < buffer.size(); ++i)
        nonzero += bytes[i] != 0;
    EXPECT_EQ(nonzero, 0u);
    std::printf("page faults for a 16 MiB buffer: %ld\n", faults);
#if !defined(PATHFARM_ASAN)  // its shadow memory is faulted in beside
    if (huge) {
        EXPECT_LT(faults, 64);
    }
#endif
}

TEST(KeepFreedMemory, AFrameLoopsBuffersAreNotFaultedInAgain) {
#if defined(PATHFARM_ASAN)
    GTEST_SKIP() << "AddressSanitizer replaces malloc";
#endif
    // Without it (in a child process, as the setting is process-wide): glibc maps the buffer
    // again every frame, and the kernel faults it in again (384 faults for 6 MiB here: 16 KiB
    // at a time).
    int fds[2];
    ASSERT_EQ(pipe(fds), 0);
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        // glibc's starting threshold (mallopt(3)): this process may have raised its own (glibc
        // does when a mapped block is freed, as HugePages.* do).
        mallopt(M_MMAP_THRESHOLD, 128 << 10);
        const long faults = refaults_per_frame(4);
        const bool written = write(fds[1], &faults, sizeof faults) == ssize_t(sizeof faults);
        _exit(written ? 0 : 1);
    }
    long without = -1;
    ASSERT_EQ(read(fds[0], &without, sizeof without), ssize_t(sizeof without));
    int status = 0;
    waitpid(child, &status, 0);
    close(fds[0]);
    close(fds[1]);
    EXPECT_GT(without, 96) << "glibc no longer maps a freed buffer afresh: this test shows "
                              "nothing";

    ASSERT_TRUE(keep_freed_memory());
    const long with = refaults_per_frame(4);
    std::printf("page faults per 6 MiB frame: %ld by default, %ld kept\n", without, with);
    EXPECT_LT(with, 16);
}

}  // namespace
}  // namespace pathfarm
