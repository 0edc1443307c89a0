// The extra-sample map's wire form: round trip, and a tracer refusing what it cannot render.
#include <gtest/gtest.h>

#include "common/film/extra_samples_codec.h"

namespace pathfarm {
namespace {

TEST(ExtraSamplesCodec, RoundTripsAndRefusesWrongSizesAndTooManySamples) {
    std::vector<uint8_t> map(320 * 180, 0);
    for (std::size_t i = 0; i < map.size(); i += 7)
        map[i] = uint8_t(i % (kMaxExtraSamples + 1));
    const std::string wire = encode_extra_samples(map);
    EXPECT_LT(wire.size(), map.size() / 4) << "mostly zeros and a pattern: small";
    auto back = decode_extra_samples(wire, 320, 180);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(*back, map);

    auto wrong = decode_extra_samples(wire, 320, 179);
    ASSERT_FALSE(wrong.ok());
    EXPECT_NE(wrong.error().message.find("extra samples"), std::string::npos)
        << wrong.error().message;
    EXPECT_FALSE(decode_extra_samples("not zstd", 320, 180).ok());
    EXPECT_FALSE(decode_extra_samples(wire, 0, 180).ok());

    map[321] = kMaxExtraSamples + 1;
    auto too_many = decode_extra_samples(encode_extra_samples(map), 320, 180);
    ASSERT_FALSE(too_many.ok());
    EXPECT_NE(too_many.error().message.find("pixel (1, 1)"), std::string::npos)
        << too_many.error().message;
}

}  // namespace
}  // namespace pathfarm
