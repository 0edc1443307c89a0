// keep_freed_memory: a frame loop's buffers, freed and allocated again at the same size, are
// not faulted in again.
#include "common/base/memory.h"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
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
