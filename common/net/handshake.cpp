// Handshake envelopes to and from protobuf.
#include "common/net/handshake.h"

#include <fmt/format.h>

#include "pathfarm/wire/v1/envelope.pb.h"

namespace pathfarm::net {
namespace {

namespace pb = ::pathfarm::wire::v1;

std::string serialise(pb::Envelope& e) {
    e.set_version(kProtocolVersion);
    return e.SerializeAsString();
}

PeerInfo peer_from_hello(const pb::Hello& h) {
    PeerInfo p;
    p.role = h.role() == pb::ROLE_CLIENT ? PeerRole::client : PeerRole::tracer;
    p.name = h.name();
    p.backend = h.capabilities().backend();
    p.threads = h.capabilities().threads();
    p.wants_bvh_nodes = h.capabilities().wants_bvh_nodes();
    for (int c : h.capabilities().codecs())
        p.codecs.push_back(c);
    return p;
}

}  // namespace

std::string hello_envelope(const PeerInfo& hello, const std::string& client_nonce) {
    pb::Envelope e;
    auto* h = e.mutable_hello();
    h->set_role(hello.role == PeerRole::tracer ? pb::ROLE_TRACER : pb::ROLE_CLIENT);
    h->set_name(hello.name);
    h->mutable_capabilities()->set_backend(hello.backend);
    h->mutable_capabilities()->set_threads(hello.threads);
    h->mutable_capabilities()->set_wants_bvh_nodes(hello.wants_bvh_nodes);
    for (int c : hello.codecs)
        h->mutable_capabilities()->add_codecs(pb::FrameCodec(c));
    h->set_client_nonce(client_nonce);
    return serialise(e);
}

std::string challenge_envelope(const std::string& server_nonce) {
    pb::Envelope e;
    e.mutable_challenge()->set_server_nonce(server_nonce);
    return serialise(e);
}

std::string proof_envelope(const std::string& mac) {
    pb::Envelope e;
    e.mutable_proof()->set_mac(mac);
    return serialise(e);
}

std::string welcome_envelope(uint64_t session_id, const std::string& server_mac) {
    pb::Envelope e;
    e.mutable_welcome()->set_session_id(session_id);
    e.mutable_welcome()->set_server_mac(server_mac);
    return serialise(e);
}

std::string error_envelope(ProtocolError code, const std::string& message) {
    pb::Envelope e;
    e.mutable_error()->set_code(pb::ErrorCode(int(code)));
    e.mutable_error()->set_message(message);
    return serialise(e);
}

HandshakeMessage decode_handshake(const std::string& envelope) {
    HandshakeMessage m;
    pb::Envelope e;
    if (!e.ParseFromString(envelope)) {
        m.message = "malformed envelope";
        return m;
    }
    if (e.version() != kProtocolVersion) {
        m.failure = ProtocolError::bad_version;
        m.message = fmt::format("protocol version {} (expected {})", e.version(), kProtocolVersion);
        return m;
    }
    using Kind = HandshakeMessage::Kind;
    if (e.has_hello()) {
        m.kind = Kind::hello;
        m.peer = peer_from_hello(e.hello());
        m.nonce = e.hello().client_nonce();
    } else if (e.has_challenge()) {
        m.kind = Kind::challenge;
        m.nonce = e.challenge().server_nonce();
    } else if (e.has_proof()) {
        m.kind = Kind::proof;
        m.mac = e.proof().mac();
    } else if (e.has_welcome()) {
        m.kind = Kind::welcome;
        m.session_id = e.welcome().session_id();
        m.mac = e.welcome().server_mac();
    } else if (e.has_error()) {
        m.kind = Kind::error;
        m.message = e.error().message();
    } else {
        m.kind = Kind::other;
    }
    return m;
}

}  // namespace pathfarm::net
