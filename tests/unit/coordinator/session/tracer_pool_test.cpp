// The tracer pool without sockets (in-memory sessions): rows re-issued after the deadline, a
// mid-frame steal with the victim's truncation (and none when the victim is nearly done), a
// tracer leaving mid-frame, snapshots for late tracers, and malformed tiles refused.
#include "coordinator/session/tracer_pool.h"

#include <optional>
#include <thread>

#include <gtest/gtest.h>

#include "common/film/first_hits.h"
#include "common/film/float_codec.h"
#include "common/wire/messages.h"
#include "tests/support/memory_session.h"

namespace pathfarm::coord {
namespace {

using test::MemorySession;

constexpr int kWidth = 8;

struct Sent {
    std::vector<wire::Assignment> assignments;
    std::vector<wire::Truncation> truncations;
    std::vector<std::string> other;  // commits and snapshots (the test's placeholder bytes)
};

Sent sent_to(MemorySession& s) {
    Sent out;
    for (const std::string& e : s.take_sent()) {
        auto m = wire::decode_for_tracer(e);
        if (m && std::holds_alternative<wire::Assignment>(*m))
            out.assignments.push_back(std::get<wire::Assignment>(*m));
        else if (m && std::holds_alternative<wire::Truncation>(*m))
            out.truncations.push_back(std::get<wire::Truncation>(*m));
        else
            out.other.push_back(e);
    }
    return out;
}

// A tile of rows [y0, y1) whose pixels all hold `value`, with first hits on `instance` if given.
std::string tile(uint64_t frame, int y0, int y1, float value,
                 std::optional<uint32_t> instance = std::nullopt) {
    std::vector<float> rgb(std::size_t(y1 - y0) * kWidth * 3, value);
    wire::Tile t{frame,
                 frame,
                 uint32_t(y0),
                 uint32_t(y1),
                 compress_floats(rgb.data(), rgb.size()),
                 uint32_t(rgb.size() * 4),
                 2.0,
                 {},
                 {},
                 {},
                 0.25};
    if (instance) {
        std::vector<FirstHit> hits(std::size_t(y1 - y0) * kWidth);
        for (FirstHit& h : hits)
            h = FirstHit{float(y0), *instance, Vec3(0, 0, 1), Rgb(value),
                         *instance == 6u ? FirstHit::kSharp : 0u};
        t.first_hits_zstd = encode_first_hits(hits.data(), hits.size());
    }
    for (int y = y0; y < y1; y += kRowsPerWorkUnit) {
        t.unit_cost_us.push_back(500);
        t.unit_rays.push_back(1000);
    }
    return wire::encode_tile(t);
}

class TracerPoolTest : public ::testing::Test {
protected:
    void start(const std::string& balancer, std::chrono::milliseconds deadline, int tracers = 2) {
        // The steal rule's clock stands still unless a test advances it.
        pool_ = std::make_unique<TracerPool>(make_balancer(balancer), deadline, [this] {
            return TracerPool::Clock::time_point(std::chrono::microseconds(clock_us_.load()));
        });
        for (int i = 0; i < tracers; ++i) {
            sessions_.push_back(
                std::make_shared<MemorySession>(uint64_t(i + 1), "t" + std::to_string(i)));
            pool_->add(sessions_.back());
        }
    }
    void begin(uint64_t frame, int height, bool first_hits = false) {
        const FrameCommit commit{&commit_, &commit_, [this](bool) {
                                     ++snapshots_;
                                     return snapshot_;
                                 }};
        pool_->begin(FrameWork{frame, kWidth, height, 1, 1.0f, 0, 4, first_hits}, commit, true);
    }
    // Waits for the frame on another thread while `respond` plays the tracers. If `respond`
    // gave up (a failed assertion), the wait is stopped after 3 s instead of hanging.
    TracerPool::Wait wait(const std::function<void()>& respond) {
        std::atomic<bool> stop{false}, done{false};
        TracerPool::Wait result = TracerPool::Wait::stopped;
        std::thread waiter([&] {
            result = pool_->wait_for_frame(stop);
            done = true;
        });
        respond();
        for (int i = 0; i < 300 && !done; ++i)
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        stop = true;
        waiter.join();
        return result;
    }

    std::atomic<int64_t> clock_us_{1'000'000};
    std::unique_ptr<TracerPool> pool_;
    std::vector<std::shared_ptr<MemorySession>> sessions_;
    std::vector<std::string> commit_{"commit"}, snapshot_{"snapshot"};
    int snapshots_ = 0;
};

TEST_F(TracerPoolTest, RowsMissingAtTheDeadlineAreReissuedToAnIdleTracer) {
    start("none", std::chrono::milliseconds(50));
    begin(0, 32);
    MemorySession &a = *sessions_[0], &b = *sessions_[1];
    const Sent to_a = sent_to(a), to_b = sent_to(b);
    ASSERT_EQ(to_a.assignments.size(), 1u);
    ASSERT_EQ(to_b.assignments.size(), 1u);
    EXPECT_EQ(to_a.assignments[0].y0, 0u);
    EXPECT_EQ(to_a.assignments[0].y1, 16u);
    EXPECT_EQ(to_b.assignments[0].y1, 32u);
    const auto result = wait([&] {
        a.deliver(tile(0, 0, 16, 1.0f));  // b never answers
        std::vector<wire::Assignment> reissued;
        for (int i = 0; i < 200 && reissued.empty(); ++i) {
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
            reissued = sent_to(a).assignments;
        }
        ASSERT_EQ(reissued.size(), 1u) << "b's rows went nowhere after the deadline";
        EXPECT_EQ(reissued[0].y0, 16u);
        EXPECT_EQ(reissued[0].y1, 32u);
        a.deliver(tile(0, 16, 32, 2.0f));
    });
    EXPECT_EQ(result, TracerPool::Wait::complete);
    const FrameOutcome out = pool_->finish();
    EXPECT_EQ(out.image.pixel(3, 5).x, 1.0f);
    EXPECT_EQ(out.image.pixel(3, 20).x, 2.0f);
    ASSERT_EQ(out.tracers.size(), 1u);  // b rendered nothing
    EXPECT_EQ(out.tracers[0].rows_delivered, 32);
}

TEST_F(TracerPoolTest, ATracerThatRanOutTakesTheTailOfTheBusiestOnesRows) {
    start("cost-predictive", std::chrono::seconds(10));
    begin(0, 64);  // no measurements yet: 32 rows each
    MemorySession &a = *sessions_[0], &b = *sessions_[1];
    sent_to(a);
    sent_to(b);
    const auto result = wait([&] {
        a.deliver(tile(0, 0, 16, 1.0f));
        a.deliver(tile(0, 16, 32, 1.0f));  // a is done; b still misses 8 units
        // a's tiles: 2 ms per 16 rows. b, not heard of since its assignment (the clock stands
        // still), is assumed as fast: 4 ms left; a starts 1 ms late, so 12 rows make both end
        // at 2.5 ms (steal_test.cpp has the arithmetic).
        const Sent to_a = sent_to(a), to_b = sent_to(b);
        ASSERT_EQ(to_a.assignments.size(), 1u);
        EXPECT_EQ(to_a.assignments[0].y0, 52u) << "the tail of b's rows";
        EXPECT_EQ(to_a.assignments[0].y1, 64u);
        ASSERT_EQ(to_b.truncations.size(), 1u);
        EXPECT_EQ(to_b.truncations[0].row, 52u) << "b stops where the stolen rows begin";
        b.deliver(tile(0, 32, 48, 2.0f));
        b.deliver(tile(0, 48, 52, 2.0f));
        a.deliver(tile(0, 52, 64, 3.0f));
    });
    EXPECT_EQ(result, TracerPool::Wait::complete);
    const FrameOutcome out = pool_->finish();
    EXPECT_EQ(out.image.pixel(0, 40).x, 2.0f);
    EXPECT_EQ(out.image.pixel(0, 60).x, 3.0f);
    ASSERT_EQ(out.tracers.size(), 2u);
    EXPECT_EQ(out.tracers[0].rows_delivered, 44);
    EXPECT_EQ(out.tracers[1].rows_delivered, 20);
}

TEST_F(TracerPoolTest, ATracerAboutToFinishKeepsItsRows) {
    start("cost-predictive", std::chrono::seconds(10));
    begin(0, 64);
    MemorySession &a = *sessions_[0], &b = *sessions_[1];
    sent_to(a);
    sent_to(b);
    const auto result = wait([&] {
        a.deliver(tile(0, 0, 16, 1.0f));
        b.deliver(tile(0, 32, 48, 2.0f));  // b: 2 ms per 16 rows
        clock_us_ += 1000;                 // 1 ms on: b has rendered 8 of its last 16 rows
        a.deliver(tile(0, 16, 32, 1.0f));
        EXPECT_TRUE(sent_to(a).assignments.empty()) << "1 ms of b's work left: not worth a steal";
        EXPECT_TRUE(sent_to(b).truncations.empty());
        b.deliver(tile(0, 48, 64, 2.0f));
    });
    EXPECT_EQ(result, TracerPool::Wait::complete);
    EXPECT_EQ(pool_->finish().tracers.at(1).rows_delivered, 32);
}

TEST_F(TracerPoolTest, ATracerLeavingMidFrameHasItsRowsReissuedAtOnce) {
    start("none", std::chrono::seconds(10));  // the deadline is not what re-issues here
    begin(0, 32);
    MemorySession &a = *sessions_[0], &b = *sessions_[1];
    sent_to(a);
    const auto result = wait([&] {
        b.deliver(tile(0, 16, 20, 5.0f));  // one unit arrives, then b dies
        b.leave("connection reset");
        const Sent to_a = sent_to(a);
        ASSERT_EQ(to_a.assignments.size(), 1u);
        EXPECT_EQ(to_a.assignments[0].y0, 20u) << "only what never arrived";
        EXPECT_EQ(to_a.assignments[0].y1, 32u);
        a.deliver(tile(0, 0, 16, 1.0f));
        a.deliver(tile(0, 20, 32, 1.0f));
    });
    EXPECT_EQ(result, TracerPool::Wait::complete);
    EXPECT_EQ(pool_->size(), 1u);
    EXPECT_EQ(pool_->finish().image.pixel(0, 17).x, 5.0f);
}

TEST_F(TracerPoolTest, ReplicasAtThePreviousCommitGetTheCommitOthersASnapshot) {
    start("none", std::chrono::seconds(10), 1);
    begin(0, 8);
    EXPECT_EQ(sent_to(*sessions_[0]).other, snapshot_) << "frame 0: a snapshot";
    wait([&] { sessions_[0]->deliver(tile(0, 0, 8, 1.0f)); });
    pool_->finish();
    auto late = std::make_shared<MemorySession>(9, "late");
    pool_->add(late);
    begin(1, 8);
    EXPECT_EQ(sent_to(*sessions_[0]).other, commit_) << "in step: frame 1's commit";
    EXPECT_EQ(sent_to(*late).other, snapshot_) << "joined late: a snapshot";
    EXPECT_EQ(snapshots_, 2);
}

// The workload scaler leaves a snapshot's one-time scene build out of what it learns from a
// frame; the outcome says which replicas came from one. A tile arriving after its frame closed
// is dropped: the finished frame's buffers have moved on to the display.
TEST_F(TracerPoolTest, OutcomesSayWhichReplicasCameFromASnapshotAndLateTilesAreDropped) {
    start("none", std::chrono::seconds(10), 1);
    begin(0, 8);
    wait([&] { sessions_[0]->deliver(tile(0, 0, 8, 1.0f)); });
    const FrameOutcome first = pool_->finish();
    ASSERT_EQ(first.tracers.size(), 1u);
    EXPECT_TRUE(first.tracers[0].from_snapshot) << "frame 0: built from a snapshot";
    ASSERT_EQ(first.image.rgb.size(), std::size_t(kWidth) * 8 * 3);
    EXPECT_EQ(first.image.rgb[5], 1.0f);
    sessions_[0]->deliver(tile(0, 0, 8, 2.0f));  // frame 0 again, after it closed
    EXPECT_TRUE(sessions_[0]->open()) << "a late tile is not malformed";
    auto late = std::make_shared<MemorySession>(9, "late");
    pool_->add(late);
    begin(1, 8);
    const auto result = wait([&] {
        sessions_[0]->deliver(tile(1, 0, 4, 3.0f));
        late->deliver(tile(1, 4, 8, 4.0f));
    });
    ASSERT_EQ(result, TracerPool::Wait::complete);
    const FrameOutcome second = pool_->finish();
    ASSERT_EQ(second.tracers.size(), 2u);
    for (const TracerFrameStats& t : second.tracers)
        EXPECT_EQ(t.from_snapshot, t.name == "late") << t.name;
    EXPECT_EQ(second.image.rgb[5], 3.0f);
    EXPECT_EQ(second.image.rgb.back(), 4.0f);
}

TEST_F(TracerPoolTest, MalformedAndMisfitTilesAreRefused) {
    start("none", std::chrono::seconds(10));
    begin(0, 16);
    sessions_[0]->deliver("not an envelope");
    EXPECT_FALSE(sessions_[0]->open());
    EXPECT_NE(sessions_[0]->rejection().find("malformed"), std::string::npos);
    sessions_[1]->deliver(tile(0, 8, 24, 1.0f));  // rows beyond the frame
    EXPECT_FALSE(sessions_[1]->open());
    EXPECT_NE(sessions_[1]->rejection().find("do not fit"), std::string::npos);
}

TEST_F(TracerPoolTest, FirstHitsAreAssembledWhenAskedAndRequiredThen) {
    start("none", std::chrono::seconds(10));
    begin(0, 16, true);
    ASSERT_TRUE(sent_to(*sessions_[0]).assignments.at(0).first_hits);
    const auto result = wait([&] {
        sessions_[0]->deliver(tile(0, 0, 8, 1.0f, 5u));
        sessions_[1]->deliver(tile(0, 8, 16, 2.0f, 6u));
    });
    ASSERT_EQ(result, TracerPool::Wait::complete);
    const FrameOutcome out = pool_->finish();
    ASSERT_EQ(out.first_hits.size(), std::size_t(kWidth) * 16);
    EXPECT_EQ(out.first_hits[std::size_t(3) * kWidth + 1].instance, 5u);
    EXPECT_EQ(out.first_hits[std::size_t(12) * kWidth + 1].instance, 6u);
    EXPECT_EQ(out.first_hits[std::size_t(12) * kWidth + 1].distance, 8.0f);
    EXPECT_EQ(out.first_hits[std::size_t(12) * kWidth + 1].albedo, Rgb(2.0f));
    EXPECT_TRUE(out.first_hits[std::size_t(12) * kWidth + 1].sharp()) << "flags cross the wire";
    EXPECT_FALSE(out.first_hits[std::size_t(3) * kWidth + 1].sharp());
    ASSERT_EQ(out.tracers.size(), 2u);
    EXPECT_EQ(out.tracers[0].update_ms, 0.25) << "the tracers' update times reach the stats";
    begin(1, 16, true);
    sessions_[0]->deliver(tile(1, 0, 8, 1.0f));  // the hits the assignment asked for are missing
    EXPECT_FALSE(sessions_[0]->open());
    EXPECT_NE(sessions_[0]->rejection().find("first hits"), std::string::npos);
    begin(2, 16);
    EXPECT_FALSE(sent_to(*sessions_[1]).assignments.back().first_hits);
    EXPECT_TRUE(pool_->finish().first_hits.empty());
}

}  // namespace
}  // namespace pathfarm::coord
