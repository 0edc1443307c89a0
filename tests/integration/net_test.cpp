// Sessions on loopback, with TLS and with --insecure-plaintext: the handshake authenticates
// both ways, messages flow, and a peer that is malformed, oversized, out of order, on the wrong
// version, unauthenticated or silent gets an Error and is disconnected while an established
// session carries on (in TLS mode the abuse comes through a TLS tunnel with the right key).
#include <condition_variable>
#include <mutex>

#include <gtest/gtest.h>

#include "common/net/auth.h"
#include "common/net/framing.h"
#include "common/net/session.h"
#include "pathfarm/wire/v1/envelope.pb.h"
#include "tests/support/raw_peer.h"

namespace pathfarm::net {
namespace {

namespace pb = ::pathfarm::wire::v1;

// Collects what server-side sessions receive.
struct Inbox {
    std::mutex mutex;
    std::condition_variable cv;
    std::vector<std::string> messages;
    std::vector<std::shared_ptr<Session>> sessions;

    void attach(std::shared_ptr<Session> s) {
        s->on_message = [this](std::string&& m) {
            std::lock_guard lock(mutex);
            messages.push_back(std::move(m));
            cv.notify_all();
        };
        s->on_closed = [](const std::string&) {};
        std::lock_guard lock(mutex);
        sessions.push_back(std::move(s));
        cv.notify_all();
    }
    bool wait_messages(std::size_t n) {
        std::unique_lock lock(mutex);
        return cv.wait_for(lock, std::chrono::seconds(5), [&] { return messages.size() >= n; });
    }
};

std::string envelope_with_input(uint64_t seq) {
    pb::Envelope e;
    e.set_version(kProtocolVersion);
    e.mutable_input()->set_sequence(seq);
    return e.SerializeAsString();
}

// The parameter: TLS on (the default) or --insecure-plaintext.
struct Fixture : ::testing::TestWithParam<bool> {
    NetService net;
    Inbox inbox;
    uint16_t port = 0;
    bool tls() const { return GetParam(); }
    void SetUp() override {
        ServerConfig config;
        config.tls = tls();
        config.bind_address = "127.0.0.1";
        config.roles = {PeerRole::tracer};
        config.secret = "correct horse";
        config.max_message_bytes = 1 << 16;
        config.handshake_timeout = std::chrono::milliseconds(300);
        auto p =
            net.listen(config, [this](std::shared_ptr<Session> s) { inbox.attach(std::move(s)); });
        ASSERT_TRUE(p.ok()) << p.error().message;
        port = *p;
    }
    ClientConfig client(const std::string& secret, PeerRole role = PeerRole::tracer) const {
        ClientConfig c;
        c.port = port;
        c.secret = secret;
        c.hello.role = role;
        c.hello.name = "test-tracer";
        c.hello.backend = "embree";
        c.hello.wants_bvh_nodes = true;
        c.on_message = [](std::string&&) {};
        c.on_closed = [](const std::string&) {};
        c.tls = tls();
        return c;
    }
    // A raw peer speaking this fixture's mode with the right secret.
    std::string raw_secret() const { return tls() ? "correct horse" : ""; }
};

INSTANTIATE_TEST_SUITE_P(Links, Fixture, ::testing::Values(true, false),
                         [](const auto& p) { return p.param ? "Tls" : "Plaintext"; });

using test::RawPeer;

std::string hello_bytes(uint32_t version = kProtocolVersion) {
    pb::Envelope e;
    e.set_version(version);
    e.mutable_hello()->set_role(pb::ROLE_TRACER);
    e.mutable_hello()->set_client_nonce(make_nonce());
    return frame(e.SerializeAsString());
}

std::optional<pb::Envelope> receive(RawPeer& peer) {
    auto body = peer.receive_frame();
    pb::Envelope e;
    if (!body || !e.ParseFromString(*body)) return std::nullopt;
    return e;
}

void expect_rejected(RawPeer& peer, pb::ErrorCode code) {
    auto e = receive(peer);
    ASSERT_TRUE(e.has_value()) << "expected an Error envelope";
    ASSERT_TRUE(e->has_error());
    EXPECT_EQ(e->error().code(), code) << e->error().message();
    EXPECT_TRUE(peer.closed_by_peer());
}

TEST_P(Fixture, HandshakeAuthenticatesAndMessagesFlow) {
    auto session = net.connect_sync(client("correct horse"));
    ASSERT_TRUE(session.ok()) << session.error().message;
    for (uint64_t i = 0; i < 100; ++i)
        (*session)->send(envelope_with_input(i));
    ASSERT_TRUE(inbox.wait_messages(100));
    pb::Envelope last;
    ASSERT_TRUE(last.ParseFromString(inbox.messages.back()));
    EXPECT_EQ(last.input().sequence(), 99u) << "in order";
    std::lock_guard lock(inbox.mutex);
    EXPECT_EQ(inbox.sessions.at(0)->peer().name, "test-tracer");
    EXPECT_TRUE(inbox.sessions.at(0)->peer().wants_bvh_nodes);
    (*session)->close("done");
}

TEST_P(Fixture, WrongSecretIsRefusedBothWays) {
    auto bad = net.connect_sync(client("wrong"));
    ASSERT_FALSE(bad.ok());
    // With TLS the key itself differs: the tunnel never opens, the HMAC is never reached.
    EXPECT_NE(bad.error().message.find(tls() ? "TLS handshake failed" : "authentication failed"),
              std::string::npos)
        << bad.error().message;
    std::lock_guard lock(inbox.mutex);
    EXPECT_TRUE(inbox.sessions.empty());
}

TEST_P(Fixture, WrongRoleIsRefused) {
    auto bad = net.connect_sync(client("correct horse", PeerRole::client));
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("role client"), std::string::npos) << bad.error().message;
}

TEST_P(Fixture, AbusivePeersAreDisconnectedAndOthersCarryOn) {
    auto good = net.connect_sync(client("correct horse"));
    ASSERT_TRUE(good.ok());
    {
        RawPeer oversized(port, raw_secret());
        ASSERT_TRUE(oversized.connected());
        const unsigned char huge[4] = {0x7f, 0xff, 0xff, 0xff};
        oversized.send_bytes(std::string(reinterpret_cast<const char*>(huge), 4));
        expect_rejected(oversized, pb::ERROR_CODE_OVERSIZED);
    }
    {
        RawPeer garbage(port, raw_secret());
        garbage.send_bytes(frame("\xff\xff\xff\xff not protobuf"));
        expect_rejected(garbage, pb::ERROR_CODE_MALFORMED);
    }
    {
        RawPeer early(port, raw_secret());
        pb::Envelope proof;
        proof.set_version(kProtocolVersion);
        proof.mutable_proof()->set_mac("guess");
        early.send_bytes(frame(proof.SerializeAsString()));
        expect_rejected(early, pb::ERROR_CODE_OUT_OF_ORDER);
    }
    {
        RawPeer old(port, raw_secret());
        old.send_bytes(hello_bytes(99));
        expect_rejected(old, pb::ERROR_CODE_BAD_VERSION);
    }
    {
        RawPeer guesser(port, raw_secret());
        guesser.send_bytes(hello_bytes());
        auto challenge = receive(guesser);
        ASSERT_TRUE(challenge && challenge->has_challenge());
        pb::Envelope proof;
        proof.set_version(kProtocolVersion);
        proof.mutable_proof()->set_mac(std::string(32, 'x'));
        guesser.send_bytes(frame(proof.SerializeAsString()));
        expect_rejected(guesser, pb::ERROR_CODE_UNAUTHENTICATED);
    }
    {
        RawPeer silent(port, raw_secret());  // says nothing: the handshake deadline closes it
        expect_rejected(silent, pb::ERROR_CODE_TIMEOUT);
    }
    (*good)->send(envelope_with_input(7));
    ASSERT_TRUE(inbox.wait_messages(1)) << "the established session is unaffected";
    std::lock_guard lock(inbox.mutex);
    EXPECT_EQ(inbox.sessions.size(), 1u) << "no abusive peer became a session";
}

TEST_P(Fixture, OversizedMessageAfterHandshakeClosesOnlyThatSession) {
    auto a = net.connect_sync(client("correct horse"));
    auto b = net.connect_sync(client("correct horse"));
    ASSERT_TRUE(a.ok() && b.ok());
    pb::Envelope big;
    big.set_version(kProtocolVersion);
    big.mutable_tile()->set_rgb_zstd(std::string(1 << 17, 'z'));  // over the 64 KiB test limit
    (*a)->send(big.SerializeAsString());
    (*b)->send(envelope_with_input(1));
    ASSERT_TRUE(inbox.wait_messages(1));
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    EXPECT_FALSE((*a)->open()) << "the server disconnected the oversized sender";
    EXPECT_TRUE((*b)->open());
}

TEST(Framing, HeaderRoundTripAndLimits) {
    unsigned char h[4];
    write_frame_header(70000, h);
    EXPECT_EQ(*read_frame_header(h, 1 << 20), 70000u);
    EXPECT_FALSE(read_frame_header(h, 1000).ok());
    write_frame_header(0, h);
    EXPECT_FALSE(read_frame_header(h, 1000).ok());
    EXPECT_EQ(frame("abc").size(), 7u);
}

TEST(Auth, MacsDependOnSecretRoleAndNonces) {
    const std::string a = make_nonce(), b = make_nonce();
    EXPECT_NE(a, b);
    EXPECT_EQ(a.size(), kNonceBytes);
    const std::string mac = client_mac("s", "tracer", a, b);
    EXPECT_TRUE(macs_equal(mac, client_mac("s", "tracer", a, b)));
    EXPECT_FALSE(macs_equal(mac, client_mac("t", "tracer", a, b)));
    EXPECT_FALSE(macs_equal(mac, client_mac("s", "client", a, b)));
    EXPECT_FALSE(macs_equal(mac, client_mac("s", "tracer", b, a)));
    EXPECT_FALSE(macs_equal(mac, server_mac("s", a, b)));
    EXPECT_FALSE(load_secret("/no/such/secret").ok());
}

}  // namespace
}  // namespace pathfarm::net
