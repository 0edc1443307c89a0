// What a tracer receives from its coordinator: commits, bulk chunks, assignments,
// truncations; a commit is decoded the whole way (with no chunks: their absence must be an
// error, not a crash).
#include <string>
#include <variant>

#include "common/commit/commit_codec.h"
#include "common/wire/messages.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    const auto in =
        pathfarm::wire::decode_for_tracer(std::string(reinterpret_cast<const char*>(data), size));
    if (!in) return 0;
    if (const auto* commit = std::get_if<pathfarm::wire::CommitPart>(&*in))
        (void)pathfarm::decode_commit(*commit->parsed, {});
    return 0;
}
