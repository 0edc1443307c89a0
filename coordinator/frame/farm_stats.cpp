// CSV writers with fixed columns.
#include "coordinator/frame/farm_stats.h"

#include <algorithm>

#include "common/base/check.h"

namespace pathfarm::coord {

CsvWriter::CsvWriter(const std::string& path, std::string_view columns) {
    if (path.empty()) return;
    out_.open(path);
    out_ << columns << '\n';
    columns_ = std::size_t(std::count(columns.begin(), columns.end(), ',')) + 1;
}

void CsvWriter::check_arity(std::size_t values) const { PF_CHECK_EQ(values, columns_); }

}  // namespace pathfarm::coord
