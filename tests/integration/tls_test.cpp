// TLS on the tracer and client links (docs/security.md): what crosses the wire is TLS records
// from the first byte in both directions with no plaintext payload in it (and the same capture
// of a --insecure-plaintext link does show the payload, so the check can fail); a plaintext
// peer on a TLS port and a TLS peer on a plaintext port are refused with one line; a silent
// peer is cut off at the TLS deadline; closing does not wait for a close_notify that never
// comes.
#include <condition_variable>
#include <mutex>
#include <thread>

#include <gtest/gtest.h>

#include "common/net/auth.h"
#include "common/net/framing.h"
#include "common/net/handshake.h"
#include "common/net/session.h"
#include "common/net/tls_psk.h"
#include "pathfarm/wire/v1/envelope.pb.h"
#include "tests/support/raw_peer.h"
#include "tests/support/tls_records.h"
#include "tools/fault-proxy/fault_proxy.h"

namespace pathfarm::net {
namespace {

namespace pb = ::pathfarm::wire::v1;
using test::RawPeer;
using tools::FaultProxy;

constexpr char kSecret[] = "tls test secret";
constexpr char kMarker[] = "PLAINTEXT-MARKER-visible-only-without-tls";

struct Server {
    NetService net;
    uint16_t port = 0;
    std::mutex mutex;
    std::condition_variable cv;
    std::vector<std::string> received;
    std::vector<std::shared_ptr<Session>> sessions;

    explicit Server(bool tls) {
        ServerConfig config;
        config.bind_address = "127.0.0.1";
        config.roles = {PeerRole::tracer};
        config.secret = kSecret;
        config.handshake_timeout = std::chrono::milliseconds(400);
        config.tls = tls;
        auto p = net.listen(config, [this](std::shared_ptr<Session> s) {
            s->on_message = [this](std::string&& m) {
                std::lock_guard lock(mutex);
                received.push_back(std::move(m));
                cv.notify_all();
            };
            s->on_closed = [](const std::string&) {};
            std::lock_guard lock(mutex);
            sessions.push_back(std::move(s));
        });
        if (p) port = *p;
    }
    bool wait_for(std::size_t n) {
        std::unique_lock lock(mutex);
        return cv.wait_for(lock, std::chrono::seconds(5), [&] { return received.size() >= n; });
    }
};

ClientConfig dial(uint16_t port, bool tls, const std::string& secret = kSecret) {
    ClientConfig c;
    c.port = port;
    c.secret = secret;
    c.tls = tls;
    c.hello.role = PeerRole::tracer;
    c.hello.name = "tls-test";
    c.handshake_timeout = std::chrono::milliseconds(2000);
    c.on_message = [](std::string&&) {};
    c.on_closed = [](const std::string&) {};
    return c;
}

std::string marked_envelope() {
    pb::Envelope e;
    e.set_version(kProtocolVersion);
    e.mutable_tile()->set_rgb_zstd(std::string(kMarker) + std::string(3000, 'x'));
    return e.SerializeAsString();
}

// Sends marked messages through a capturing proxy; returns what it saw each way.
std::pair<std::string, std::string> capture(bool tls) {
    Server server(tls);
    FaultProxy relay(server.port);
    relay.capture();
    NetService client_net;
    auto session = client_net.connect_sync(dial(relay.port(), tls));
    EXPECT_TRUE(session.ok()) << session.error().message;
    if (!session.ok()) return {};
    for (int i = 0; i < 20; ++i)
        (*session)->send(marked_envelope());
    EXPECT_TRUE(server.wait_for(20));
    {
        std::lock_guard lock(server.mutex);
        for (auto& s : server.sessions)
            s->send(marked_envelope());  // and the other way
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    return {relay.captured(FaultProxy::Direction::to_target),
            relay.captured(FaultProxy::Direction::from_target)};
}

TEST(Tls, EveryByteOnTheWireIsATlsRecordAndThePayloadIsHidden) {
    const auto [up, down] = capture(true);
    ASSERT_GT(up.size(), 20u * 3000u);
    ASSERT_GT(down.size(), 3000u);
    EXPECT_EQ(static_cast<unsigned char>(up[0]), 22) << "the first byte opens a handshake record";
    EXPECT_EQ(static_cast<unsigned char>(down[0]), 22);
    for (const std::string* bytes : {&up, &down}) {
        const auto scan = test::scan_tls_records(*bytes);
        EXPECT_TRUE(scan.all_records) << "after " << scan.records << " records";
        EXPECT_GT(scan.application_data, 0);
        EXPECT_EQ(bytes->find(kMarker), std::string::npos) << "payload in the clear";
        EXPECT_EQ(bytes->find("tls-test"), std::string::npos) << "Hello in the clear";
    }
}

TEST(Tls, TheSameCaptureOfAPlaintextLinkShowsThePayload) {  // the check above can fail
    const auto [up, down] = capture(false);
    EXPECT_NE(up.find(kMarker), std::string::npos);
    EXPECT_NE(down.find(kMarker), std::string::npos);
    EXPECT_FALSE(test::scan_tls_records(up).all_records);
}

TEST(Tls, APlaintextPeerOnATlsPortIsRefused) {
    Server server(true);
    RawPeer plain(server.port);
    ASSERT_TRUE(plain.connected());
    pb::Envelope hello;
    hello.set_version(kProtocolVersion);
    hello.mutable_hello()->set_role(pb::ROLE_TRACER);
    hello.mutable_hello()->set_client_nonce(make_nonce());
    plain.send_bytes(frame(hello.SerializeAsString()));
    EXPECT_FALSE(plain.receive_frame().has_value()) << "nothing readable comes back";
    EXPECT_TRUE(plain.closed_by_peer());
    std::lock_guard lock(server.mutex);
    EXPECT_TRUE(server.sessions.empty());
    NetService net;  // a real client that skips TLS: one clear error
    auto refused = net.connect_sync(dial(server.port, false));
    ASSERT_FALSE(refused.ok());
}

TEST(Tls, ATlsPeerOnAPlaintextPortIsToldWhy) {
    Server server(false);
    NetService net;
    auto refused = net.connect_sync(dial(server.port, true));
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("TLS handshake failed"), std::string::npos)
        << refused.error().message;
    EXPECT_NE(refused.error().message.find("--insecure-plaintext"), std::string::npos);
}

TEST(Tls, ASilentPeerIsCutOffAtTheTlsDeadline) {
    Server server(true);
    RawPeer silent(server.port);  // connects, never sends a ClientHello
    ASSERT_TRUE(silent.connected());
    const auto start = std::chrono::steady_clock::now();
    EXPECT_TRUE(silent.closed_by_peer());
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
}

TEST(Tls, CloseDoesNotWaitForAnAbsentCloseNotify) {
    // The raw TLS peer never answers the server's close_notify; the server must still close
    // the TCP connection (its shutdown timer), which closed_by_peer waits for (3 s at most).
    Server server(true);
    RawPeer peer(server.port, kSecret);
    ASSERT_TRUE(peer.connected());
    pb::Envelope proof;  // out of order: the server sends an Error and closes
    proof.set_version(kProtocolVersion);
    proof.mutable_proof()->set_mac("early");
    peer.send_bytes(frame(proof.SerializeAsString()));
    auto body = peer.receive_frame();
    pb::Envelope e;
    ASSERT_TRUE(body && e.ParseFromString(*body) && e.has_error());
    EXPECT_TRUE(peer.closed_by_peer(/*answer=*/false));
}

// An established session (its reader waiting for messages) closed by the server, to a peer
// that never answers close_notify: the TCP connection must still close. The cancelled
// reader used to cancel the shutdown's timer, leaving the socket open for good.
TEST(Tls, ClosingAnEstablishedSessionDoesNotWaitForTheSilentPeer) {
    Server server(true);
    RawPeer peer(server.port, kSecret);
    ASSERT_TRUE(peer.connected());
    PeerInfo hello;
    hello.role = PeerRole::tracer;
    hello.name = "silent-at-close";
    const std::string client_nonce = make_nonce();
    peer.send_bytes(frame(hello_envelope(hello, client_nonce)));
    const auto challenge = decode_handshake(peer.receive_frame().value_or(""));
    ASSERT_EQ(challenge.kind, HandshakeMessage::Kind::challenge);
    peer.send_bytes(
        frame(proof_envelope(client_mac(kSecret, "tracer", client_nonce, challenge.nonce))));
    ASSERT_EQ(decode_handshake(peer.receive_frame().value_or("")).kind,
              HandshakeMessage::Kind::welcome);
    std::shared_ptr<Session> session;
    for (int i = 0; i < 100 && !session; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        std::lock_guard lock(server.mutex);
        if (!server.sessions.empty()) session = server.sessions.front();
    }
    ASSERT_TRUE(session);
    session->close("bye");
    EXPECT_TRUE(peer.closed_by_peer(/*answer=*/false)) << "the server kept the socket open";
}

TEST(Tls, TheKeyExchangeIsEphemeralOnTopOfThePsk) {  // forward secrecy: psk_dhe_ke
    Server server(true);
    RawPeer peer(server.port, kSecret);
    ASSERT_TRUE(peer.connected());
    EXPECT_NE(peer.key_exchange_group(), 0) << "a PSK-only handshake: no forward secrecy";
}

TEST(Tls, ThePskDependsOnTheSecretAndIsNotTheSecret) {
    EXPECT_EQ(tls_psk("a").size(), 32u);
    EXPECT_EQ(tls_psk("a"), tls_psk("a"));
    EXPECT_NE(tls_psk("a"), tls_psk("b"));
    EXPECT_NE(tls_psk("secret"), std::string("secret"));
}

}  // namespace
}  // namespace pathfarm::net
