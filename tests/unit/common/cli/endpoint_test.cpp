// HOST:PORT parsing shared by the tracer's --coordinator and the client's --connect.
#include <gtest/gtest.h>

#include "common/cli/command_line.h"

namespace pathfarm {
namespace {

TEST(ParseEndpoint, SplitsAtTheLastColon) {
    auto e = parse_endpoint("--connect", "127.0.0.1:9000");
    ASSERT_TRUE(e) << e.error().message;
    EXPECT_EQ(e->host, "127.0.0.1");
    EXPECT_EQ(e->port, 9000);
    auto v6 = parse_endpoint("--connect", "[::1]:65535");
    ASSERT_TRUE(v6) << v6.error().message;
    EXPECT_EQ(v6->host, "[::1]");
    EXPECT_EQ(v6->port, 65535);
}

TEST(ParseEndpoint, RejectsWhatIsNotHostColonPort) {
    for (const char* bad : {"nowhere", ":9000", "host:", "host:0", "host:65536", "host:9000x",
                            "host:-1", "host: 90", ""}) {
        auto e = parse_endpoint("--coordinator", bad);
        ASSERT_FALSE(e) << bad;
        EXPECT_EQ(e.error().message, std::string("--coordinator ") + bad +
                                         ": expected HOST:PORT with a port in [1, 65535]");
    }
}

}  // namespace
}  // namespace pathfarm
