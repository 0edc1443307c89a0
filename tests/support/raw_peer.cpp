#include "tests/support/raw_peer.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <openssl/ssl.h>

#include "common/net/tls_psk.h"

namespace pathfarm::test {

RawPeer::RawPeer(uint16_t port, const std::string& tls_secret)
    : fd_(socket(AF_INET, SOCK_STREAM, 0)) {
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(port);
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    timeval tv{3, 0};
    setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));
    connected_ = ::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) == 0;
    if (!connected_ || tls_secret.empty()) return;
    psk_ = net::tls_psk(tls_secret);
    ctx_ = SSL_CTX_new(TLS_client_method());
    ssl_ = ctx_ != nullptr && net::use_farm_psk(ctx_, false, &psk_).ok() ? SSL_new(ctx_) : nullptr;
    connected_ = ssl_ != nullptr && SSL_set_fd(ssl_, fd_) == 1 && SSL_connect(ssl_) == 1;
}

RawPeer::~RawPeer() {
    if (ssl_ != nullptr) SSL_free(ssl_);
    if (ctx_ != nullptr) SSL_CTX_free(ctx_);
    ::close(fd_);
}

int RawPeer::key_exchange_group() const {
    return ssl_ != nullptr ? SSL_get_negotiated_group(ssl_) : 0;
}

void RawPeer::send_bytes(const std::string& b) {
    if (ssl_ != nullptr)
        (void)SSL_write(ssl_, b.data(), int(b.size()));
    else
        (void)::send(fd_, b.data(), b.size(), MSG_NOSIGNAL);
}

std::optional<std::string> RawPeer::receive_frame() {
    unsigned char header[4];
    if (!read_all(header, 4)) return std::nullopt;
    const uint32_t n = (uint32_t(header[0]) << 24) | (uint32_t(header[1]) << 16) |
                       (uint32_t(header[2]) << 8) | header[3];
    std::string body(n, '\0');
    if (!read_all(body.data(), n)) return std::nullopt;
    return body;
}

bool RawPeer::closed_by_peer(bool answer) {
    char c;
    if (ssl_ != nullptr) {
        const int r = SSL_read(ssl_, &c, 1);
        if (r > 0 || SSL_get_error(ssl_, r) != SSL_ERROR_ZERO_RETURN) return false;
        if (answer) SSL_shutdown(ssl_);
    }
    return ::recv(fd_, &c, 1, 0) == 0;
}

bool RawPeer::read_all(void* p, std::size_t n) {
    auto* c = static_cast<char*>(p);
    while (n > 0) {
        const long r = ssl_ != nullptr ? SSL_read(ssl_, c, int(n)) : ::recv(fd_, c, n, 0);
        if (r <= 0) return false;
        c += r;
        n -= std::size_t(r);
    }
    return true;
}

}  // namespace pathfarm::test
