// Row balancing (Brigade §4.3): before a frame starts, give each tracer one contiguous range
// of 4-row work units so that they finish together. Pure: no I/O, no clock; the farm and the
// simulation harness (tools/balance-sim) drive the same code.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "coordinator/balance/row_range.h"

namespace pathfarm::coord {

// What one tracer did last frame.
struct TracerFrame {
    RowRange rows;           // its range (empty: it did not render last frame, e.g. it just joined)
    double render_ms = 0.0;  // measured time for those rows
    // Cost (in BalanceInput::unit_cost's measure) it delivered per millisecond, when known. It
    // differs from the cost of `rows` over render_ms when rows moved between tracers mid-frame.
    double cost_per_ms = 0.0;
};

struct BalanceInput {
    int height = 0;
    // Tracers of this frame, in row order; last[i] is tracer i's previous frame.
    std::vector<TracerFrame> last;
    // Cost of each work unit last frame in a speed-independent measure (rays traced, or time
    // at one reference speed), so that units rendered by tracers of different speeds compare.
    // Empty: unknown.
    std::vector<double> unit_cost;
};

class Balancer {
public:
    virtual ~Balancer() = default;
    virtual std::string name() const = 0;
    // Whether the scheme also re-issues rows inside a frame: a tracer that ran out takes part
    // of another's rows (coordinator/balance/steal.h).
    virtual bool steals_mid_frame() const { return false; }
    // One range per tracer, contiguous, in order, covering [0, height) exactly once, cut on
    // work-unit boundaries.
    virtual std::vector<RowRange> assign(const BalanceInput& input) = 0;
};

// Ours smooths each tracer's measured speed over frames, s = a m + (1 - a) s: one frame's
// measurement is noisy, and re-cutting on it made the split swing by a few units a frame in
// the live farm (docs/balancing.md). 0.35 measured best there; 1 is no smoothing.
inline constexpr double kDefaultSpeedSmoothing = 0.35;

// none, robin-hood, perfect, perfect-smooth (smooth_alpha on the shares), cost-predictive
// (also "ours"; speed_smoothing on the speeds); nullptr for an unknown name.
std::unique_ptr<Balancer> make_balancer(const std::string& name, double smooth_alpha = 0.25,
                                        double speed_smoothing = kDefaultSpeedSmoothing);
std::vector<std::string> balancer_names();

int work_units(int height);
// Ranges from unit counts per tracer (in order).
std::vector<RowRange> ranges_from_units(const std::vector<int>& units, int height);
// Unit counts proportional to shares (largest-remainder rounding), summing to total.
std::vector<int> units_from_shares(const std::vector<double>& shares, int total);

}  // namespace pathfarm::coord
