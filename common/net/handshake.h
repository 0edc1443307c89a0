// The handshake's envelopes (DESIGN.md, "Protocol"): Hello, Challenge, AuthProof, Welcome and
// Error, encoded and decoded here so that the session code handles bytes and plain structs.
// Protobuf stays inside handshake.cpp, Asio inside session.cpp.
#pragma once

#include <cstdint>
#include <string>

#include "common/net/framing.h"
#include "common/net/session.h"

namespace pathfarm::net {

std::string hello_envelope(const PeerInfo& hello, const std::string& client_nonce);
std::string challenge_envelope(const std::string& server_nonce);
std::string proof_envelope(const std::string& mac);
std::string welcome_envelope(uint64_t session_id, const std::string& server_mac);
std::string error_envelope(ProtocolError code, const std::string& message);

struct HandshakeMessage {
    enum class Kind { invalid, hello, challenge, proof, welcome, error, other };
    Kind kind = Kind::invalid;
    PeerInfo peer;            // hello: role, name and capabilities (address and id unset)
    std::string nonce;        // hello: the client's nonce; challenge: the server's
    std::string mac;          // proof, welcome
    uint64_t session_id = 0;  // welcome
    std::string message;      // error: the peer's message; invalid: what was wrong
    ProtocolError failure = ProtocolError::malformed;  // invalid: the code to reject with
};

// Parses one envelope of the handshake. Kind::invalid (with failure and message) for bytes
// that are not an envelope or carry another protocol version; Kind::other for any message
// that is not part of the handshake.
HandshakeMessage decode_handshake(const std::string& envelope);

}  // namespace pathfarm::net
