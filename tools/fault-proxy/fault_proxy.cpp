#include "tools/fault-proxy/fault_proxy.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <deque>
#include <string>

namespace pathfarm::tools {
namespace {

using Clock = std::chrono::steady_clock;

int64_t now_ns() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch())
        .count();
}

sockaddr_in loopback(uint16_t port) {
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(port);
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    return addr;
}

// Closes with RST instead of FIN: what a crashed peer or a middlebox cutting the line looks
// like to the other end.
void reset(int fd) {
    linger l{1, 0};
    setsockopt(fd, SOL_SOCKET, SO_LINGER, &l, sizeof(l));
    ::close(fd);
}

struct Chunk {
    int64_t due_ns;
    std::string bytes;
};

}  // namespace

struct FaultProxy::Link {
    int fd[2] = {-1, -1};  // 0: the dialling side, 1: the target
    uint64_t half_open_epoch = 0;
    std::thread thread;
};

FaultProxy::FaultProxy(uint16_t target_port, uint16_t listen_port) : target_port_(target_port) {
    listen_fd_ = socket(AF_INET, SOCK_STREAM, 0);
    int one = 1;
    setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
    sockaddr_in addr = loopback(listen_port);
    socklen_t len = sizeof(addr);
    if (bind(listen_fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0 ||
        listen(listen_fd_, 16) != 0 ||
        getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&addr), &len) != 0)
        return;
    port_ = ntohs(addr.sin_port);
    acceptor_ = std::thread([this] { accept_loop(); });
}

FaultProxy::~FaultProxy() {
    stop_ = true;
    if (acceptor_.joinable()) acceptor_.join();
    std::list<Link> links;  // joined outside the lock: a link thread may wait for it to capture
    {
        std::lock_guard lock(mutex_);
        links.splice(links.begin(), links_);
    }
    for (Link& link : links)
        if (link.thread.joinable()) link.thread.join();
    ::close(listen_fd_);
}

void FaultProxy::stall(std::chrono::milliseconds duration) {
    stalled_until_ns_ = now_ns() + std::chrono::nanoseconds(duration).count();
}

void FaultProxy::reset_after(uint64_t bytes, Direction d) {
    reset_at_[int(d)] = int64_t(forwarded_[int(d)] + bytes);
}

void FaultProxy::half_open() { ++half_open_epoch_; }

std::string FaultProxy::captured(Direction d) const {
    std::lock_guard lock(mutex_);
    return captured_[int(d)];
}

void FaultProxy::accept_loop() {
    while (!stop_) {
        pollfd p{listen_fd_, POLLIN, 0};
        if (poll(&p, 1, 50) <= 0) continue;
        const int client = accept(listen_fd_, nullptr, nullptr);
        if (client < 0) continue;
        const int target = socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in addr = loopback(target_port_);
        if (connect(target, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0) {
            ::close(target);
            ::close(client);
            continue;
        }
        int one = 1;
        setsockopt(client, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
        setsockopt(target, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
        ++accepted_;
        std::lock_guard lock(mutex_);
        Link& link = links_.emplace_back();
        link.fd[0] = client;
        link.fd[1] = target;
        link.half_open_epoch = half_open_epoch_;
        link.thread = std::thread([this, &link] { pump(link); });
    }
}

void FaultProxy::forwarded(int dir, const std::string& bytes, std::size_t n) {
    forwarded_[dir] += n;
    if (!capturing_) return;
    std::lock_guard lock(mutex_);
    captured_[dir].append(bytes, 0, n);
}

// Reads what arrives on either side into a queue per direction, each chunk due `latency`
// after its arrival, and writes due chunks at most at the bandwidth cap; faults are checked
// between steps.
void FaultProxy::pump(Link& link) {
    std::deque<Chunk> queue[2];  // index: the side the bytes go to (1: target)
    char buffer[1 << 15];
    bool open[2] = {true, true};
    int64_t next_send_ns[2] = {0, 0};
    while (!stop_) {
        if (half_open_epoch_ != link.half_open_epoch) {  // hold the sockets, move nothing
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
            continue;
        }
        const int64_t now = now_ns();
        const bool stalled = now < stalled_until_ns_;
        pollfd p[2] = {{link.fd[0], short(open[0] && !stalled ? POLLIN : 0), 0},
                       {link.fd[1], short(open[1] && !stalled ? POLLIN : 0), 0}};
        poll(p, 2, 5);
        for (int side = 0; side < 2; ++side) {
            if ((p[side].revents & (POLLIN | POLLHUP | POLLERR)) == 0) continue;
            const ssize_t n = ::recv(link.fd[side], buffer, sizeof(buffer), 0);
            if (n <= 0) {  // pass the close on once what is queued has gone
                open[side] = false;
                continue;
            }
            queue[1 - side].push_back(
                {now_ns() + int64_t(latency_ms_) * 1'000'000, std::string(buffer, std::size_t(n))});
        }
        for (int to = 0; to < 2 && !stalled; ++to) {
            const int dir = to == 1 ? int(Direction::to_target) : int(Direction::from_target);
            while (!queue[to].empty() && queue[to].front().due_ns <= now_ns() &&
                   next_send_ns[to] <= now_ns()) {
                std::string& bytes = queue[to].front().bytes;
                std::size_t n = std::min<std::size_t>(bytes.size(), 16384);
                const int64_t reset_at = reset_at_[dir];
                const bool cut = reset_at >= 0 && int64_t(forwarded_[dir] + n) >= reset_at;
                if (cut) n = std::size_t(std::max<int64_t>(0, reset_at - int64_t(forwarded_[dir])));
                if (n > 0 && ::send(link.fd[to], bytes.data(), n, MSG_NOSIGNAL) != ssize_t(n)) {
                    open[0] = open[1] = false;
                    break;
                }
                forwarded(dir, bytes, n);
                if (cut) {
                    reset_at_[dir] = -1;
                    reset(link.fd[0]);
                    reset(link.fd[1]);
                    link.fd[0] = link.fd[1] = -1;
                    return;
                }
                bytes.erase(0, n);
                if (bytes.empty()) queue[to].pop_front();
                if (const uint64_t cap = bandwidth_; cap > 0)
                    next_send_ns[to] = now_ns() + int64_t(n * 1'000'000'000 / cap);
            }
        }
        // A side that closed: once the other direction's queue has drained, close both.
        if ((!open[0] && queue[1].empty()) || (!open[1] && queue[0].empty())) break;
    }
    for (int fd : link.fd)
        if (fd >= 0) ::close(fd);
    link.fd[0] = link.fd[1] = -1;
}

}  // namespace pathfarm::tools
