// Routing and access control, apart from the server so that they are tested without sockets.
#include "coordinator/http/http_routes.h"

#include <algorithm>
#include <fstream>
#include <sstream>

#include <openssl/crypto.h>
#include <openssl/rand.h>

namespace pathfarm::coord {
namespace {

constexpr std::string_view kCookieName = "pathfarm_token";

std::string_view path_of(std::string_view resource) {
    return resource.substr(0, resource.find('?'));
}

HttpResponse text(int status, std::string body) {
    return HttpResponse{status, "text/plain; charset=utf-8", std::move(body), {}};
}

bool token_char(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' ||
           c == '_';
}

// Finds name=value among `separator`-separated pairs (spaces around pairs ignored).
std::optional<std::string_view> pair_value(std::string_view pairs, std::string_view name,
                                           char separator) {
    while (!pairs.empty()) {
        const std::size_t end = std::min(pairs.find(separator), pairs.size());
        std::string_view pair = pairs.substr(0, end);
        pairs.remove_prefix(std::min(end + 1, pairs.size()));
        while (!pair.empty() && pair.front() == ' ')
            pair.remove_prefix(1);
        const std::size_t eq = pair.find('=');
        if (eq != std::string_view::npos && pair.substr(0, eq) == name) return pair.substr(eq + 1);
    }
    return std::nullopt;
}

}  // namespace

std::string random_token() {
    unsigned char bytes[16];
    if (RAND_bytes(bytes, sizeof bytes) != 1) throw std::runtime_error("RAND_bytes failed");
    static constexpr char kHex[] = "0123456789abcdef";
    std::string token;
    for (const unsigned char b : bytes) {
        token += kHex[b >> 4];
        token += kHex[b & 15];
    }
    return token;
}

Result<std::string> read_token_file(const std::string& path) {
    std::ifstream in(path);
    if (!in) return make_error(ErrorCode::not_found, "--http-token-file {}: cannot open", path);
    std::stringstream text;
    text << in.rdbuf();
    std::string token = text.str();
    const auto not_space = [](unsigned char c) { return !std::isspace(c); };
    token.erase(token.begin(), std::find_if(token.begin(), token.end(), not_space));
    token.erase(std::find_if(token.rbegin(), token.rend(), not_space).base(), token.end());
    if (token.size() < kMinTokenChars || !std::all_of(token.begin(), token.end(), token_char))
        return make_error(ErrorCode::invalid_argument,
                          "--http-token-file {}: the token must be at least {} characters of "
                          "A-Z, a-z, 0-9, '-' and '_'",
                          path, kMinTokenChars);
    return token;
}

bool same_token(std::string_view given, std::string_view token) {
    return given.size() == token.size() &&
           CRYPTO_memcmp(given.data(), token.data(), token.size()) == 0;
}

std::optional<std::string_view> query_value(std::string_view resource, std::string_view name) {
    const std::size_t q = resource.find('?');
    if (q == std::string_view::npos) return std::nullopt;
    return pair_value(resource.substr(q + 1), name, '&');
}

std::optional<std::string_view> cookie_value(std::string_view cookie, std::string_view name) {
    return pair_value(cookie, name, ';');
}

bool HttpRoutes::authorised(const HttpRequest& r) const {
    const auto given = query_value(r.resource, "token");
    if (given) return same_token(*given, token_);
    const auto cookie = cookie_value(r.cookie, kCookieName);
    return cookie && same_token(*cookie, token_);
}

HttpResponse HttpRoutes::handle(const HttpRequest& r) const {
    if (r.method != "GET" && r.method != "HEAD") return text(405, "GET only\n");
    const std::string_view path = path_of(r.resource);
    if (path == "/healthz") return text(200, "ok\n");
    if (!authorised(r)) return text(403, "forbidden: open the URL the coordinator printed\n");
    if (path == "/metrics")
        return HttpResponse{200, "text/plain; version=0.0.4; charset=utf-8", metrics_(), {}};
    if (path == "/ws") return text(400, "/ws is a WebSocket\n");
    const WebAsset* asset = find_web_asset(path == "/" ? "/index.html" : path);
    if (!asset) return text(404, "not found\n");
    HttpResponse page{200, std::string(asset->content_type), std::string(asset->body), {}};
    // The page's own requests (scripts, the WebSocket) carry the token from here on.
    page.headers.emplace_back("Set-Cookie", std::string(kCookieName) + "=" + token_ +
                                                "; Path=/; HttpOnly; SameSite=Strict");
    return page;
}

std::optional<HttpResponse> HttpRoutes::upgrade(const HttpRequest& r) const {
    if (path_of(r.resource) != "/ws") return text(404, "not found\n");
    if (!authorised(r)) return text(403, "forbidden\n");
    return std::nullopt;
}

}  // namespace pathfarm::coord
