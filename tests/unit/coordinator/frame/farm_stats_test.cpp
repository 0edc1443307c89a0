// The farm's CSV writers: the header is the column list, rows have exactly its arity, and the
// docs quote every list exactly (so help text and docs cannot go stale).
#include "coordinator/frame/farm_stats.h"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "tests/support/test_env.h"

namespace pathfarm::coord {
namespace {

std::string read_file(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

TEST(FarmStats, WritesTheHeaderAndRowsOfItsColumns) {
    const std::string path = test::scratch_dir() + "/stages.csv";
    {
        CsvWriter csv(path, kStageColumns);
        ASSERT_TRUE(csv.active());
        csv.row(3, 0.5, 1.25, 180.0, 2, 0.75);
    }
    EXPECT_EQ(read_file(path), std::string(kStageColumns) + "\n3,0.5,1.25,180,2,0.75\n");
    CsvWriter none("", kStageColumns);
    EXPECT_FALSE(none.active());
    none.row(1, 2);  // writes nothing, checks nothing
}

TEST(FarmStatsDeathTest, ARowOfTheWrongArityIsABug) {
    const std::string path = test::scratch_dir() + "/bad.csv";
    EXPECT_DEATH(
        {
            CsvWriter csv(path, kUnitCostColumns);
            csv.row(1, 2);
        },
        "");
}

TEST(FarmStats, TheDocsQuoteEveryColumnListExactly) {
    const std::string doc = read_file(std::string(PATHFARM_SOURCE_DIR) + "/docs/farm.md");
    ASSERT_FALSE(doc.empty());
    for (std::string_view columns : {kFrameStatsColumns, kTracerStatsColumns, kStageColumns,
                                     kUnitCostColumns, kOfflineStatsColumns})
        EXPECT_NE(doc.find("`" + std::string(columns) + "`"), std::string::npos)
            << "docs/farm.md does not quote " << columns;
}

}  // namespace
}  // namespace pathfarm::coord
