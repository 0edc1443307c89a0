#include "tests/support/tcp_relay.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

namespace pathfarm::test {
namespace {

sockaddr_in loopback(uint16_t port) {
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(port);
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    return addr;
}

}  // namespace

TcpRelay::TcpRelay(uint16_t target_port) : target_port_(target_port) {
    listen_fd_ = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr = loopback(0);
    socklen_t len = sizeof(addr);
    if (bind(listen_fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0 ||
        listen(listen_fd_, 4) != 0 ||
        getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&addr), &len) != 0)
        return;
    port_ = ntohs(addr.sin_port);
    thread_ = std::thread([this] { run(); });
}

TcpRelay::~TcpRelay() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    ::close(listen_fd_);
}

std::string TcpRelay::from_client() const {
    std::lock_guard lock(mutex_);
    return from_client_;
}

std::string TcpRelay::from_server() const {
    std::lock_guard lock(mutex_);
    return from_server_;
}

void TcpRelay::run() {
    while (!stop_) {
        pollfd p{listen_fd_, POLLIN, 0};
        if (poll(&p, 1, 50) <= 0) continue;
        const int client = accept(listen_fd_, nullptr, nullptr);
        if (client < 0) continue;
        const int server = socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in addr = loopback(target_port_);
        if (connect(server, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) == 0)
            pump(client, server);
        ::close(server);
        ::close(client);
    }
}

void TcpRelay::pump(int client, int server) {
    char buffer[1 << 16];
    while (!stop_) {
        pollfd p[2] = {{client, POLLIN, 0}, {server, POLLIN, 0}};
        if (poll(p, 2, 50) <= 0) continue;
        for (int i = 0; i < 2; ++i) {
            if ((p[i].revents & (POLLIN | POLLHUP | POLLERR)) == 0) continue;
            const ssize_t n = ::recv(p[i].fd, buffer, sizeof(buffer), 0);
            if (n <= 0) return;
            {
                std::lock_guard lock(mutex_);
                (i == 0 ? from_client_ : from_server_).append(buffer, std::size_t(n));
            }
            if (::send(p[1 - i].fd, buffer, std::size_t(n), MSG_NOSIGNAL) != n) return;
        }
    }
}

TlsRecordScan scan_tls_records(const std::string& bytes) {
    TlsRecordScan scan;
    std::size_t at = 0;
    while (at + 5 <= bytes.size()) {
        const auto type = static_cast<unsigned char>(bytes[at]);
        const auto major = static_cast<unsigned char>(bytes[at + 1]);
        const auto minor = static_cast<unsigned char>(bytes[at + 2]);
        const std::size_t length = (std::size_t(static_cast<unsigned char>(bytes[at + 3])) << 8) |
                                   static_cast<unsigned char>(bytes[at + 4]);
        // 20 change_cipher_spec, 21 alert, 22 handshake, 23 application_data; TLS 1.3 writes
        // 0x0303 (0x0301 in the first ClientHello).
        if (type < 20 || type > 23 || major != 3 || (minor != 1 && minor != 3)) return scan;
        if (length > (1u << 14) + 256) return scan;
        at += 5 + length;
        ++scan.records;
        scan.application_data += type == 23;
    }
    scan.all_records = scan.records > 0;  // a record still in flight may be cut at the end
    return scan;
}

}  // namespace pathfarm::test
