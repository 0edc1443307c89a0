#include "common/net/tls_psk.h"

#include <cstring>

#include <openssl/err.h>
#include <openssl/evp.h>
#include <openssl/hmac.h>
#include <openssl/ssl.h>

namespace pathfarm::net {
namespace {

// TLS_AES_128_GCM_SHA256: the PSK session's cipher fixes the handshake hash (SHA-256), which
// every suite allowed here shares.
constexpr unsigned char kAes128GcmSha256[] = {0x13, 0x01};

// An ex_data slot of our own: Asio keeps its verify callback in the context's app data (and
// deletes whatever it finds there).
int psk_slot() {
    static const int slot = SSL_CTX_get_ex_new_index(0, nullptr, nullptr, nullptr, nullptr);
    return slot;
}

const std::string* psk_of(SSL* ssl) {
    return static_cast<const std::string*>(SSL_CTX_get_ex_data(SSL_get_SSL_CTX(ssl), psk_slot()));
}

SSL_SESSION* psk_session(SSL* ssl, const std::string& psk) {
    const SSL_CIPHER* cipher = SSL_CIPHER_find(ssl, kAes128GcmSha256);
    SSL_SESSION* session = SSL_SESSION_new();
    if (cipher == nullptr || session == nullptr ||
        !SSL_SESSION_set1_master_key(session, reinterpret_cast<const unsigned char*>(psk.data()),
                                     psk.size()) ||
        !SSL_SESSION_set_cipher(session, cipher) ||
        !SSL_SESSION_set_protocol_version(session, TLS1_3_VERSION)) {
        SSL_SESSION_free(session);
        return nullptr;
    }
    return session;
}

// Client: offer the farm PSK (ownership of the session passes to OpenSSL).
int use_session(SSL* ssl, const EVP_MD* md, const unsigned char** id, std::size_t* id_len,
                SSL_SESSION** out) {
    SSL_SESSION* session = psk_session(ssl, *psk_of(ssl));
    if (session == nullptr) return 0;
    if (md != nullptr && SSL_CIPHER_get_handshake_digest(SSL_SESSION_get0_cipher(session)) != md) {
        SSL_SESSION_free(session);  // a retry asked for another hash: offer nothing
        *out = nullptr;
        *id = nullptr;
        *id_len = 0;
        return 1;
    }
    *out = session;
    *id = reinterpret_cast<const unsigned char*>(kTlsPskIdentity.data());
    *id_len = kTlsPskIdentity.size();
    return 1;
}

// Server: the farm PSK for the farm's identity, nothing otherwise (the handshake then fails:
// there is no certificate to fall back to). A wrong secret fails the binder check.
int find_session(SSL* ssl, const unsigned char* id, std::size_t id_len, SSL_SESSION** out) {
    *out = nullptr;
    if (id_len != kTlsPskIdentity.size() || std::memcmp(id, kTlsPskIdentity.data(), id_len) != 0)
        return 1;
    *out = psk_session(ssl, *psk_of(ssl));
    return *out != nullptr ? 1 : 0;
}

}  // namespace

std::string tls_psk(std::string_view secret) {
    static constexpr std::string_view kLabel = "pathfarm/v1/tls-psk";
    unsigned char mac[EVP_MAX_MD_SIZE];
    unsigned int n = 0;
    HMAC(EVP_sha256(), secret.data(), int(secret.size()),
         reinterpret_cast<const unsigned char*>(kLabel.data()), kLabel.size(), mac, &n);
    return std::string(reinterpret_cast<const char*>(mac), n);
}

Status use_farm_psk(ssl_ctx_st* ctx, bool server, const std::string* psk) {
    if (psk == nullptr || psk->size() != 32)
        return make_error(ErrorCode::invalid_argument, "TLS: the PSK must be 32 bytes");
    if (!SSL_CTX_set_min_proto_version(ctx, TLS1_3_VERSION) ||
        !SSL_CTX_set_max_proto_version(ctx, TLS1_3_VERSION) ||
        !SSL_CTX_set_ciphersuites(ctx, "TLS_AES_128_GCM_SHA256:TLS_CHACHA20_POLY1305_SHA256"))
        return make_error(ErrorCode::io_error, "TLS: {}", take_tls_error());
    // No session tickets: every connection authenticates with the farm PSK afresh, and a
    // resumption ticket would outlive a rotated secret.
    SSL_CTX_set_options(ctx, SSL_OP_NO_TICKET);
    SSL_CTX_set_num_tickets(ctx, 0);
    if (psk_slot() < 0 || !SSL_CTX_set_ex_data(ctx, psk_slot(), const_cast<std::string*>(psk)))
        return make_error(ErrorCode::io_error, "TLS: {}", take_tls_error());
    if (server)
        SSL_CTX_set_psk_find_session_callback(ctx, find_session);
    else
        SSL_CTX_set_psk_use_session_callback(ctx, use_session);
    return {};
}

std::string take_tls_error() {
    const unsigned long code = ERR_get_error();
    ERR_clear_error();
    if (code == 0) return "unknown TLS error";
    const char* reason = ERR_reason_error_string(code);
    return reason != nullptr ? reason : "TLS error " + std::to_string(code);
}

}  // namespace pathfarm::net
