// The glb loader on a file holding the input (every loaded scene is also validated).
#include "common/scene/load/scene_loader.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    (void)pathfarm::load_scene(pathfarm::fuzz::write_input_file(data, size, ".glb"));
    return 0;
}
