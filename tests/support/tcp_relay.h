// A TCP relay on loopback for tests: forwards one connection at a time to a target port and
// records every byte each way, to check what crosses the wire (TLS records from the first
// byte, no plaintext payload). Threads and blocking sockets; stops with the object.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

namespace pathfarm::test {

class TcpRelay {
public:
    explicit TcpRelay(uint16_t target_port);
    ~TcpRelay();
    TcpRelay(const TcpRelay&) = delete;
    TcpRelay& operator=(const TcpRelay&) = delete;

    uint16_t port() const { return port_; }
    // What the dialling side sent and what the target sent back, so far.
    std::string from_client() const;
    std::string from_server() const;

private:
    void run();
    void pump(int client, int server);

    uint16_t target_port_;
    uint16_t port_ = 0;
    int listen_fd_ = -1;
    std::atomic<bool> stop_{false};
    mutable std::mutex mutex_;
    std::string from_client_, from_server_;
    std::thread thread_;
};

// Splits a byte stream into TLS records (type, version, length): all_records is false when a
// header has an unknown type, version or an oversized length (the last record may be cut).
struct TlsRecordScan {
    bool all_records = false;
    int records = 0;
    int application_data = 0;  // content type 23
};
TlsRecordScan scan_tls_records(const std::string& bytes);

}  // namespace pathfarm::test
