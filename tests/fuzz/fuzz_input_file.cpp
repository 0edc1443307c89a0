#include "tests/fuzz/fuzz_input_file.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace pathfarm::fuzz {

std::string write_input_file(const uint8_t* data, std::size_t size, const std::string& extension) {
    static const std::filesystem::path dir = [] {
        const std::filesystem::path base = std::filesystem::exists("/dev/shm")
                                               ? "/dev/shm"
                                               : std::filesystem::temp_directory_path();
        auto d = base / ("pathfarm-fuzz-" + std::to_string(getpid()));
        std::filesystem::create_directories(d);
        return d;
    }();
    const std::string path = (dir / ("input" + extension)).string();
    std::ofstream(path, std::ios::binary | std::ios::trunc)
        .write(reinterpret_cast<const char*>(data), std::streamsize(size));
    return path;
}

}  // namespace pathfarm::fuzz
