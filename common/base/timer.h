// Wall-clock stopwatch for statistics (never for the game clock: DESIGN.md, "Time").
#pragma once

#include <chrono>

namespace pathfarm {

class Timer {
public:
    Timer() : start_(Clock::now()) {}
    void reset() { start_ = Clock::now(); }
    double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
    double milliseconds() const { return seconds() * 1e3; }

private:
    using Clock = std::chrono::steady_clock;
    Clock::time_point start_;
};

}  // namespace pathfarm
