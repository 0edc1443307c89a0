// The bench tools' command lines are positional: each has a usage text that --help (or -h)
// prints to stdout with exit 0, and that a wrong count of arguments prints to stderr with
// exit 2.
#pragma once

#include <cstdio>
#include <cstring>

namespace pathfarm::bench {

// The exit code when the process must end now (help asked, or `count_ok` false), else -1.
inline int usage_exit(int argc, char** argv, bool count_ok, const char* usage) {
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
            std::fputs(usage, stdout);
            return 0;
        }
    if (count_ok) return -1;
    std::fputs(usage, stderr);
    return 2;
}

}  // namespace pathfarm::bench
