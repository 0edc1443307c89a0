// The HTTP port's routing and access control, without sockets (the metrics and browser tests
// in tests/integration/web run them through a real server).
#include <filesystem>
#include <fstream>
#include <set>

#include <gtest/gtest.h>

#include "coordinator/http/http_routes.h"

namespace pathfarm::coord {
namespace {

const std::string kToken = "0123456789abcdef0123456789abcdef";

HttpRoutes routes() {
    return HttpRoutes(kToken, [] { return std::string("pathfarm_frames_total 3\n"); });
}

HttpRequest get(std::string resource, std::string cookie = "") {
    return {"GET", std::move(resource), std::move(cookie)};
}

TEST(HttpRoutes, HealthzIsOpenAndEverythingElseNeedsTheToken) {
    const HttpRoutes r = routes();
    EXPECT_EQ(r.handle(get("/healthz")).status, 200);
    for (const char* path :
         {"/", "/index.html", "/app.js", "/style.css", "/metrics", "/ws", "/x"}) {
        EXPECT_EQ(r.handle(get(path)).status, 403) << path;
        EXPECT_EQ(r.handle(get(std::string(path) + "?token=" + kToken.substr(1))).status, 403);
        EXPECT_EQ(r.handle(get(std::string(path) + "?token=")).status, 403);
        EXPECT_EQ(r.handle(get(path, "pathfarm_token=wrong")).status, 403);
        EXPECT_EQ(r.handle(get(path, "other=" + kToken)).status, 403);
        EXPECT_TRUE(r.upgrade(get(path)));  // refused
    }
    EXPECT_EQ(r.handle(get("/metrics?token=" + kToken)).status, 200);
    EXPECT_EQ(r.handle(get("/metrics?a=1&token=" + kToken + "&b=2")).body,
              "pathfarm_frames_total 3\n");
    EXPECT_EQ(r.handle(get("/metrics", "a=b; pathfarm_token=" + kToken)).status, 200);
    EXPECT_EQ(r.handle(get("/nothing?token=" + kToken)).status, 404);
    EXPECT_EQ(r.handle({"POST", "/metrics?token=" + kToken, ""}).status, 405);
}

TEST(HttpRoutes, ThePageSetsTheTokenCookieForItsOwnRequests) {
    const HttpResponse page = routes().handle(get("/?token=" + kToken));
    ASSERT_EQ(page.status, 200);
    EXPECT_NE(page.content_type.find("text/html"), std::string::npos);
    EXPECT_NE(page.body.find("app.js"), std::string::npos);
    ASSERT_EQ(page.headers.size(), 1u);
    EXPECT_EQ(page.headers[0].first, "Set-Cookie");
    EXPECT_EQ(page.headers[0].second.rfind("pathfarm_token=" + kToken + ";", 0), 0u);
    EXPECT_NE(page.headers[0].second.find("HttpOnly"), std::string::npos);
    EXPECT_NE(page.headers[0].second.find("SameSite=Strict"), std::string::npos);
}

TEST(HttpRoutes, TheWebSocketIsOnlyAtWsWithTheToken) {
    const HttpRoutes r = routes();
    EXPECT_FALSE(r.upgrade(get("/ws?token=" + kToken)));
    EXPECT_FALSE(r.upgrade(get("/ws", "pathfarm_token=" + kToken)));
    EXPECT_EQ(r.upgrade(get("/ws"))->status, 403);
    EXPECT_EQ(r.upgrade(get("/metrics?token=" + kToken))->status, 404);
}

TEST(HttpRoutes, EveryClientFileIsServedWithItsType) {
    for (const auto& [path, type] : {std::pair{"/index.html", "text/html"},
                                     {"/app.js", "text/javascript"},
                                     {"/style.css", "text/css"}}) {
        const WebAsset* a = find_web_asset(path);
        ASSERT_NE(a, nullptr) << path;
        EXPECT_EQ(a->content_type.rfind(type, 0), 0u);
        EXPECT_GT(a->body.size(), 100u);
    }
    EXPECT_EQ(find_web_asset("/../CMakeLists.txt"), nullptr);
}

TEST(HttpTokens, RandomTokensAreLongHexAndDistinct) {
    std::set<std::string> seen;
    for (int k = 0; k < 100; ++k) {
        const std::string t = random_token();
        ASSERT_EQ(t.size(), 32u);
        ASSERT_EQ(t.find_first_not_of("0123456789abcdef"), std::string::npos);
        seen.insert(t);
    }
    EXPECT_EQ(seen.size(), 100u);
    EXPECT_TRUE(same_token(kToken, kToken));
    EXPECT_FALSE(same_token(kToken.substr(0, 31), kToken));
    EXPECT_FALSE(same_token(kToken + "0", kToken));
}

TEST(HttpTokens, TokenFilesAreTrimmedAndChecked) {
    const auto path = std::filesystem::temp_directory_path() / "pathfarm_http_token_test";
    const auto write = [&](const std::string& text) { std::ofstream(path) << text; };
    write("  abcdefghij_KLMNOP-0123\n");
    auto t = read_token_file(path.string());
    ASSERT_TRUE(t) << t.error().message;
    EXPECT_EQ(*t, "abcdefghij_KLMNOP-0123");
    write("short\n");
    EXPECT_FALSE(read_token_file(path.string()));
    write("abcdefghijklmnop qrs\n");  // a space inside: it would not survive a URL
    auto bad = read_token_file(path.string());
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find(path.string()), std::string::npos);
    std::filesystem::remove(path);
    EXPECT_EQ(read_token_file(path.string()).error().code, ErrorCode::not_found);
}

TEST(HttpTokens, QueryAndCookieValues) {
    EXPECT_EQ(query_value("/p?x=1&a=2", "a"), "2");
    EXPECT_EQ(query_value("/p?ax=1", "a"), std::nullopt);
    EXPECT_EQ(query_value("/p", "a"), std::nullopt);
    EXPECT_EQ(cookie_value("x=1; a=2", "a"), "2");
    EXPECT_EQ(cookie_value("xa=1", "a"), std::nullopt);
}

}  // namespace
}  // namespace pathfarm::coord
