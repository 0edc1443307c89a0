// Encodes a tracer's tiles (zstd) and sends them on a thread of its own, in the order they were
// rendered, while the render threads go on with the next tile. Encoding on the render thread
// left a multi-threaded tracer's other threads waiting between tiles (about 2 ms a frame at
// 320x180 on this machine's tracers): a serial part that grows against a render that shrinks
// with more cores.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "common/film/first_hits.h"
#include "common/wire/messages.h"

namespace pathfarm::tracer {

class TileSender {
public:
    using Send = std::function<void(std::string envelope)>;
    // A rendered tile: its pixels (RGB floats, row by row) and its first hits if they were
    // asked for (else none; already in the coordinator's instance ids); `tile` has everything
    // else, its render_ms the render's (the encoding's time is added).
    struct Job {
        wire::Tile tile;
        std::vector<float> rgb;
        std::vector<FirstHit> hits;
    };

    explicit TileSender(Send send);
    ~TileSender();  // sends what is queued, then stops
    TileSender(const TileSender&) = delete;
    TileSender& operator=(const TileSender&) = delete;

    void submit(Job job);
    // Returns once every submitted tile has been handed to Send.
    void flush();

private:
    void run();

    Send send_;
    std::mutex mutex_;
    std::condition_variable work_, done_;
    std::deque<Job> jobs_;
    bool busy_ = false;
    bool stopping_ = false;
    std::thread thread_;  // last: started once the rest exists
};

}  // namespace pathfarm::tracer
