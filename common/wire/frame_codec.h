// How a frame travels to a client (wire FrameCodec values): the client names the codecs it
// accepts in its Hello, the coordinator encodes each frame once per codec in use.
#pragma once

namespace pathfarm::wire {

enum class FrameCodec : int { png = 1, float_zstd = 2, jpeg = 3, h264 = 4 };

}  // namespace pathfarm::wire
