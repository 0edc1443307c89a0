// The browser client's messages: layouts round-trip, and any bytes a page could send are
// either refused with a reason or decoded into a bounded input.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "coordinator/http/web_protocol.h"

namespace pathfarm::coord {
namespace {

TEST(WebProtocol, FrameHeaderRoundTripsAndPrecedesThePicture) {
    const WebFrameHeader h{WebCodec::h264,     false, 320,      180, 160, 90, 2,
                           123456789012345ull, 77,    987654321};
    const std::string m = encode_web_frame(h, "JPEGDATA");
    ASSERT_EQ(m.size(), kWebFrameHeaderBytes + 8);
    EXPECT_EQ(m.substr(kWebFrameHeaderBytes), "JPEGDATA");
    auto back = decode_web_frame_header(m);
    ASSERT_TRUE(back) << back.error().message;
    EXPECT_EQ(back->codec, WebCodec::h264);
    EXPECT_FALSE(back->key);
    EXPECT_EQ(back->width, 320);
    EXPECT_EQ(back->height, 180);
    EXPECT_EQ(back->render_width, 160);
    EXPECT_EQ(back->render_height, 90);
    EXPECT_EQ(back->spp, 2);
    EXPECT_EQ(back->frame, h.frame);
    EXPECT_EQ(back->last_input_sequence, 77u);
    EXPECT_EQ(back->sent_us, 987654321u);
    // The page reads these offsets (coordinator/http/web/app.js).
    EXPECT_EQ(m.substr(0, 4), "PFWF");
    EXPECT_EQ(uint8_t(m[5]), 1);  // codec
    EXPECT_EQ(uint8_t(m[6]), 0);  // flags: not a key picture
    EXPECT_EQ(uint8_t(m[8]), 320 & 255);
    EXPECT_EQ(uint8_t(m[24]), 0x79);  // frame, little-endian: 123456789012345 = 0x7048860DDF79
    EXPECT_EQ(uint8_t(m[32]), 77);
}

TEST(WebProtocol, InputRoundTripsWithinTheBounds) {
    PlayerInput in;
    in.sequence = 1ull << 40;
    in.move = {0.25f, -1.0f, 2.0f, 0.1f, -0.2f};
    in.action = true;
    auto back = decode_web_input(encode_web_input(in));
    ASSERT_TRUE(back) << back.error().message;
    EXPECT_EQ(back->sequence, in.sequence);
    EXPECT_EQ(back->move, in.move);
    EXPECT_TRUE(back->action);
    EXPECT_FALSE(back->camera_to_world);
}

TEST(WebProtocol, OutOfRangeAndNonFiniteMovesAreBounded) {
    PlayerInput in;
    in.move = {1e9f, -INFINITY, NAN, 100.0f, -100.0f};
    auto back = decode_web_input(encode_web_input(in));
    ASSERT_TRUE(back);
    EXPECT_EQ(back->move[0], 10.0f);
    EXPECT_EQ(back->move[1], 0.0f);
    EXPECT_EQ(back->move[2], 0.0f);
    EXPECT_FLOAT_EQ(back->move[3], 3.14159265f);
    EXPECT_FLOAT_EQ(back->move[4], -3.14159265f);
}

TEST(WebProtocol, MalformedInputsAreRefusedWithAReason) {
    const std::string good = encode_web_input(PlayerInput{});
    EXPECT_FALSE(decode_web_input(good.substr(0, 35)));
    EXPECT_FALSE(decode_web_input(good + "x"));
    EXPECT_FALSE(decode_web_input(""));
    for (const std::size_t at : {0, 3, 4}) {  // magic, version
        std::string bad = good;
        bad[at] ^= 0x20;
        EXPECT_FALSE(decode_web_input(bad)) << at;
    }
    for (const std::size_t at : {5, 6, 7}) {  // unknown flag bits, reserved bytes
        std::string bad = good;
        bad[at] = char(0x02);
        const auto r = decode_web_input(bad);
        ASSERT_FALSE(r) << at;
        EXPECT_NE(r.error().message.find("web input"), std::string::npos);
    }
}

// Random bytes (any size, and 36-byte messages with the right header) never decode into an
// input the game could not take: every move finite and within the bounds.
TEST(WebProtocol, RandomBytesAreRefusedOrBounded) {
    std::mt19937 rng(20261202);
    std::uniform_int_distribution<int> byte(0, 255);
    int decoded = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        std::string m(trial % 2 ? kWebInputBytes : std::size_t(rng() % 80), '\0');
        for (char& c : m)
            c = char(byte(rng));
        if (trial % 2 && trial % 4 == 1) {
            m.replace(0, 5, std::string("PFWI\x01", 5));
            m[5] = char(rng() % 2);
            m[6] = m[7] = 0;
        }
        const auto in = decode_web_input(m);
        if (!in) continue;
        ++decoded;
        for (std::size_t k = 0; k < in->move.size(); ++k) {
            ASSERT_TRUE(std::isfinite(in->move[k]));
            ASSERT_LE(std::abs(in->move[k]), k < 3 ? 10.0f : 3.1416f);
        }
    }
    EXPECT_GE(decoded, 4000);  // the well-formed quarter decodes
}

}  // namespace
}  // namespace pathfarm::coord
