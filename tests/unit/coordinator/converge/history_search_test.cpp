// Converging's footprint search (history_search.h): at an edge, the history comes from the
// nearest pixel beside the point's own that saw the same surface, never from one beside a
// moving object, and nothing is found where no pixel within one of the point saw it.
#include <vector>

#include <gtest/gtest.h>

#include "coordinator/converge/history_search.h"

namespace pathfarm::coord {
namespace {

// A 6x4 last frame: instance 1 (a wall at distance 10) left of x = 3, instance 2 (a box at
// distance 5) from x = 3 on.
GBuffer edge_frame() {
    GBuffer g;
    g.resize(6, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 6; ++x) {
            const std::size_t i = std::size_t(y) * 6 + x;
            g.instance[i] = x < 3 ? 1 : 2;
            g.distance[i] = x < 3 ? 10.0f : 5.0f;
        }
    return g;
}

TEST(HistorySearch, AnEdgePointTakesTheNearestPixelOfItsSurface) {
    const GBuffer g = edge_frame();
    // The wall's point fell just right of the edge, in the box's pixel (3, 1).
    int hx = 3, hy = 1;
    ASSERT_FALSE(same_surface(g, std::size_t(hy) * 6 + hx, 1, 10.0f, 0.03f));
    EXPECT_TRUE(search_footprint(g, nullptr, 1, 10.0f, 0.03f, 3.2f, 1.6f, hx, hy));
    EXPECT_EQ(hx, 2);
    EXPECT_EQ(hy, 1);
    // Nearer the pixel below than the one left of it: the pixel below (3, 2) is box too, so the
    // search goes on to the left one and then the diagonal.
    hx = 3, hy = 1;
    EXPECT_TRUE(search_footprint(g, nullptr, 1, 10.0f, 0.03f, 3.45f, 1.95f, hx, hy));
    EXPECT_EQ(hx, 2);
    EXPECT_EQ(hy, 1);
}

TEST(HistorySearch, NoPixelBesideAMovingObjectAndNoOtherDepth) {
    const GBuffer g = edge_frame();
    std::vector<uint8_t> near_prev(24, 0);
    for (int y = 0; y < 4; ++y)
        near_prev[std::size_t(y) * 6 + 2] = 1;  // the wall's column next to the box
    int hx = 3, hy = 1;
    EXPECT_FALSE(search_footprint(g, near_prev.data(), 1, 10.0f, 0.03f, 3.2f, 1.6f, hx, hy));
    EXPECT_EQ(hx, 3);  // left where it was
    hx = 3, hy = 1;    // the same instance, but 20 % nearer: another surface of it
    EXPECT_FALSE(search_footprint(g, nullptr, 1, 8.0f, 0.03f, 3.2f, 1.6f, hx, hy));
    hx = 4, hy = 1;  // two pixels from the wall: nothing within one pixel of the point
    EXPECT_FALSE(search_footprint(g, nullptr, 1, 10.0f, 0.03f, 4.2f, 1.5f, hx, hy));
}

TEST(HistorySearch, TheImageBorderIsNotCrossed) {
    GBuffer g = edge_frame();
    int hx = 0, hy = 0;  // a box point in the wall's corner pixel, its nearer sides outside
    EXPECT_FALSE(search_footprint(g, nullptr, 2, 5.0f, 0.03f, 0.1f, 0.1f, hx, hy));
    g.instance[1] = 2, g.distance[1] = 5.0f;  // now the box is also at (1, 0)
    hx = 0, hy = 0;
    EXPECT_TRUE(search_footprint(g, nullptr, 2, 5.0f, 0.03f, 0.9f, 0.1f, hx, hy));
    EXPECT_EQ(hx, 1);
    EXPECT_EQ(hy, 0);
}

}  // namespace
}  // namespace pathfarm::coord
