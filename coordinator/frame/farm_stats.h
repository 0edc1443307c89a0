// The farm's CSV outputs (docs/farm.md, "Statistics"): one writer per file, and each file's
// columns listed once, here. The coordinator's --help and docs/farm.md quote these lists (a
// test checks the docs against them).
#pragma once

#include <fstream>
#include <string>
#include <string_view>

namespace pathfarm::coord {

inline constexpr std::string_view kFrameStatsColumns =
    "frame,tracers,frame_ms,idle_pct,commit_bytes,tile_bytes,spp,rr_scale,render_width,"
    "render_height,f,kept,at_floor,display_ms,wall_ms,denoise_ms";
inline constexpr std::string_view kTracerStatsColumns =
    "frame,tracer,first_row,rows,render_ms,rows_delivered,update_ms";
inline constexpr std::string_view kStageColumns =
    "frame,send_ms,prepare_next_ms,wait_tiles_ms,assemble_ms,prepare_ms";
inline constexpr std::string_view kUnitCostColumns = "frame,unit,cost_us";
// pathfarm-coordinator --offline --stats-csv
inline constexpr std::string_view kOfflineStatsColumns =
    "frame,commit_bytes,animate_ms,accel_ms,commit_ms,dynamic_tris,replica_ok";

// A CSV file with a fixed column list: the header at open, then rows of exactly that many
// values, flushed as they are written (tests and live monitoring read them while the farm
// runs). A writer without a path writes nothing.
class CsvWriter {
public:
    CsvWriter() = default;
    CsvWriter(const std::string& path, std::string_view columns);
    bool active() const { return out_.is_open(); }
    bool good() const { return !out_.is_open() || out_.good(); }

    template <typename... Values>
    void row(const Values&... values) {
        if (!out_.is_open()) return;
        check_arity(sizeof...(Values));
        std::size_t k = 0;
        ((out_ << (k++ ? "," : "") << values), ...);
        out_ << '\n';
        out_.flush();
    }

private:
    void check_arity(std::size_t values) const;
    std::ofstream out_;
    std::size_t columns_ = 0;
};

}  // namespace pathfarm::coord
