// Shared-secret authentication: HMAC-SHA256 challenge-response, the secret never on the wire.
#pragma once

#include <string>
#include <string_view>

#include "common/base/result.h"

namespace pathfarm::net {

inline constexpr std::size_t kNonceBytes = 32;

// Cryptographically random bytes (OpenSSL RAND_bytes).
std::string make_nonce();
// What the connecting peer proves: HMAC(secret, "pathfarm/v1/client" | role | nonces).
std::string client_mac(std::string_view secret, std::string_view role,
                       std::string_view client_nonce, std::string_view server_nonce);
// What the server proves back: HMAC(secret, "pathfarm/v1/server" | nonces).
std::string server_mac(std::string_view secret, std::string_view client_nonce,
                       std::string_view server_nonce);
// Constant-time comparison.
bool macs_equal(std::string_view a, std::string_view b);

// The shared secret from --secret-file (first line, trimmed) or else $PATHFARM_SECRET. Empty
// or missing is an error naming where it looked.
Result<std::string> load_secret(const std::string& secret_file);

}  // namespace pathfarm::net
