// The tracer's tile sender: tiles go out in the order they were submitted, compressed as the
// frame worker compressed them inline before, all of them by flush(), and the ones still
// queued when it is destroyed are sent too.
#include "tracer-node/tile_sender.h"

#include <mutex>
#include <thread>

#include <gtest/gtest.h>

#include "common/film/float_codec.h"
#include "common/wire/messages.h"

namespace pathfarm::tracer {
namespace {

TileSender::Job job(uint32_t y0, int width, bool with_hits) {
    TileSender::Job j;
    j.tile = wire::Tile{7, 3, y0, y0 + 16, {}, 0, 0.0, {}, {}, {}, 0.0};
    j.rgb.resize(std::size_t(16) * width * 3);
    for (std::size_t i = 0; i < j.rgb.size(); ++i)
        j.rgb[i] = float(y0) + 0.001f * float(i % 97);
    if (with_hits) {
        j.hits.resize(std::size_t(16) * width);
        for (std::size_t i = 0; i < j.hits.size(); ++i)
            j.hits[i] = FirstHit{1.0f + float(i),
                                 uint32_t(i % 5),
                                 Vec3(0, 0, 1),
                                 Rgb(0.5f),
                                 0u,
                                 FirstHit::kNone,
                                 0.0f,
                                 0.0f};
    }
    j.tile.raw_bytes = uint32_t(j.rgb.size() * sizeof(float));
    return j;
}

struct Received {
    std::mutex mutex;
    std::vector<std::string> envelopes;
    void add(std::string e) {
        std::lock_guard lock(mutex);
        envelopes.push_back(std::move(e));
    }
};

TEST(TileSender, SendsEveryTileInOrderByFlush) {
    Received got;
    TileSender sender([&got](std::string e) {
        std::this_thread::sleep_for(std::chrono::microseconds(200));  // slower than submitting
        got.add(std::move(e));
    });
    std::vector<TileSender::Job> expected;
    for (uint32_t k = 0; k < 40; ++k) {
        expected.push_back(job(16 * k, 64, k % 3 != 0));
        sender.submit(job(16 * k, 64, k % 3 != 0));
    }
    sender.flush();
    ASSERT_EQ(got.envelopes.size(), expected.size());
    for (std::size_t k = 0; k < expected.size(); ++k) {
        auto tile = wire::decode_tile(got.envelopes[k]);
        ASSERT_TRUE(tile.ok()) << tile.error().message;
        EXPECT_EQ(tile->y0, expected[k].tile.y0) << "tile " << k;
        EXPECT_EQ(tile->rgb_zstd, compress_floats(expected[k].rgb.data(), expected[k].rgb.size()));
        EXPECT_EQ(tile->first_hits_zstd,
                  !expected[k].hits.empty()
                      ? encode_first_hits(expected[k].hits.data(), expected[k].hits.size())
                      : std::string());
    }
    sender.submit(job(640, 64, false));  // flush() again after more work
    sender.flush();
    EXPECT_EQ(got.envelopes.size(), expected.size() + 1);
    sender.flush();  // nothing queued: returns at once
}

// flush() must also wait for the tile being sent, not only for the queue to empty.
TEST(TileSender, FlushWaitsForTheTileInFlight) {
    Received got;
    TileSender sender([&got](std::string e) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        got.add(std::move(e));
    });
    sender.submit(job(0, 16, false));
    std::this_thread::sleep_for(std::chrono::milliseconds(10));  // taken off the queue by now
    sender.flush();
    EXPECT_EQ(got.envelopes.size(), 1u);
}

TEST(TileSender, SendsWhatIsQueuedWhenDestroyed) {
    Received got;
    {
        TileSender sender([&got](std::string e) {
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
            got.add(std::move(e));
        });
        for (uint32_t k = 0; k < 20; ++k)
            sender.submit(job(16 * k, 32, true));
    }
    ASSERT_EQ(got.envelopes.size(), 20u);
    for (uint32_t k = 0; k < 20; ++k)
        EXPECT_EQ(wire::decode_tile(got.envelopes[k])->y0, 16 * k);
}

}  // namespace
}  // namespace pathfarm::tracer
