// The client hub's back-pressure: a native client that has not taken its last frames skips
// the next one instead of queueing it (a queue is latency, and a client that never reads
// must not hold frames forever), and an H.264 client that skipped one gets a key picture next
// (its decoder could not use a delta after the gap).
#include "coordinator/session/client_hub.h"

#include <gtest/gtest.h>

#include "common/film/h264_codec.h"
#include "common/wire/frame_codec.h"
#include "common/wire/messages.h"
#include "tests/support/memory_session.h"

namespace pathfarm::coord {
namespace {

FloatImage picture(int frame) {
    FloatImage image(64, 48);
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            for (int c = 0; c < 3; ++c)
                image.rgb[(std::size_t(y) * image.width + x) * 3 + c] =
                    0.2f + 0.6f * float((x + 3 * frame + c * y) % 17) / 17.0f;
    return image;
}

struct Hub {
    FarmMetrics metrics;
    ClientHub hub{90, metrics};
    std::shared_ptr<test::MemorySession> add(uint64_t id, wire::FrameCodec codec) {
        auto s = std::make_shared<test::MemorySession>(id, "client");
        s->set_codecs({int(codec)});
        hub.add(s);
        return s;
    }
    void show(int frame) { hub.send(picture(frame), ShownFrame{uint64_t(frame), 64, 48, 1}); }
};

TEST(ClientHubBackPressure, AClientNotReadingSkipsFramesAndTheOthersDoNot) {
    Hub h;
    auto slow = h.add(1, wire::FrameCodec::jpeg);
    auto fast = h.add(2, wire::FrameCodec::jpeg);
    h.show(0);
    EXPECT_EQ(slow->take_sent().size(), 1u);
    slow->unsent = 64u << 20;  // 64 MiB still unsent: it is not reading
    h.show(1);
    h.show(2);
    EXPECT_TRUE(slow->take_sent().empty()) << "frames skipped, not queued";
    EXPECT_EQ(fast->take_sent().size(), 3u);
    slow->unsent = 0;  // caught up
    h.show(3);
    const auto sent = slow->take_sent();
    ASSERT_EQ(sent.size(), 1u);
    EXPECT_EQ(wire::decode_frame(sent[0])->frame, 3u);
    EXPECT_TRUE(slow->open());
}

TEST(ClientHubBackPressure, AnH264ClientResumesAtAKeyPicture) {
    Hub h;
    auto client = h.add(1, wire::FrameCodec::h264);
    auto decoder = H264Decoder::open();
    ASSERT_TRUE(decoder.ok());
    for (int f = 0; f < 3; ++f) {
        h.show(f);
        for (const auto& m : client->take_sent())
            ASSERT_TRUE((*decoder)->decode(wire::decode_frame(m)->data).ok()) << f;
    }
    client->unsent = 64u << 20;
    h.show(3);  // skipped
    client->unsent = 0;
    h.show(4);
    const auto sent = client->take_sent();
    ASSERT_EQ(sent.size(), 1u);
    // A decoder that never saw the stream must be able to start here: an IDR picture.
    auto fresh = H264Decoder::open();
    ASSERT_TRUE(fresh.ok());
    EXPECT_TRUE((*fresh)->decode(wire::decode_frame(sent[0])->data).ok())
        << "after a skipped picture the next one must be a key picture";
}

}  // namespace
}  // namespace pathfarm::coord
