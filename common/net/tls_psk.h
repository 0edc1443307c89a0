// TLS 1.3 with an external pre-shared key derived from the farm secret (docs/security.md):
// every tracer and client link is encrypted and mutually authenticated by the secret operators
// already distribute, with an ephemeral (EC)DHE exchange on top for forward secrecy. No
// certificates: the secret is the credential. OpenSSL stays inside tls_psk.cpp; callers hand
// in their SSL_CTX (Asio's ssl::context in session.cpp, a blocking one in tests).
#pragma once

#include <string>
#include <string_view>

#include "common/base/result.h"

struct ssl_ctx_st;

namespace pathfarm::net {

inline constexpr std::string_view kTlsPskIdentity = "pathfarm/v1";

// The 32-byte PSK: HMAC-SHA256(secret, "pathfarm/v1/tls-psk"); a key of its own, so that the
// HMAC challenge inside the tunnel and the tunnel's key never share bytes.
std::string tls_psk(std::string_view secret);

// Restricts ctx to TLS 1.3 with TLS_AES_128_GCM_SHA256 / TLS_CHACHA20_POLY1305_SHA256 and the
// psk_dhe_ke mode, and installs the PSK callbacks (client: offer the farm PSK; server: accept
// only it). *psk must outlive ctx.
Status use_farm_psk(ssl_ctx_st* ctx, bool server, const std::string* psk);

// The oldest queued OpenSSL error as text (and the queue cleared), for one-line logs.
std::string take_tls_error();

}  // namespace pathfarm::net
