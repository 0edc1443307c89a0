// HMAC-SHA256 through OpenSSL.
#include "common/net/auth.h"

#include <cstdlib>
#include <fstream>

#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/hmac.h>
#include <openssl/rand.h>

namespace pathfarm::net {
namespace {

std::string hmac(std::string_view key, std::string_view message) {
    unsigned char out[EVP_MAX_MD_SIZE];
    unsigned int len = 0;
    HMAC(EVP_sha256(), key.data(), int(key.size()),
         reinterpret_cast<const unsigned char*>(message.data()), message.size(), out, &len);
    return std::string(reinterpret_cast<const char*>(out), len);
}

}  // namespace

std::string make_nonce() {
    std::string nonce(kNonceBytes, '\0');
    if (RAND_bytes(reinterpret_cast<unsigned char*>(nonce.data()), int(nonce.size())) != 1)
        std::abort();
    return nonce;
}

std::string client_mac(std::string_view secret, std::string_view role,
                       std::string_view client_nonce, std::string_view server_nonce) {
    std::string msg = "pathfarm/v1/client|";
    msg.append(role).append("|").append(client_nonce).append(server_nonce);
    return hmac(secret, msg);
}

std::string server_mac(std::string_view secret, std::string_view client_nonce,
                       std::string_view server_nonce) {
    std::string msg = "pathfarm/v1/server|";
    msg.append(client_nonce).append(server_nonce);
    return hmac(secret, msg);
}

bool macs_equal(std::string_view a, std::string_view b) {
    return a.size() == b.size() && CRYPTO_memcmp(a.data(), b.data(), a.size()) == 0;
}

Result<std::string> load_secret(const std::string& secret_file) {
    std::string secret;
    if (!secret_file.empty()) {
        std::ifstream in(secret_file);
        if (!in)
            return make_error(ErrorCode::not_found, "--secret-file {}: cannot read", secret_file);
        std::getline(in, secret);
        while (!secret.empty() &&
               (secret.back() == '\r' || secret.back() == ' ' || secret.back() == '\t'))
            secret.pop_back();
        if (secret.empty())
            return make_error(ErrorCode::invalid_argument, "--secret-file {}: empty secret",
                              secret_file);
        return secret;
    }
    if (const char* env = std::getenv("PATHFARM_SECRET"); env != nullptr && *env != '\0')
        return std::string(env);
    return make_error(ErrorCode::invalid_argument,
                      "no shared secret: pass --secret-file FILE or set PATHFARM_SECRET");
}

}  // namespace pathfarm::net
