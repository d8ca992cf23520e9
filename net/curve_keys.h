// CURVE keys for broker connections (docs/security.md): generating a key pair, reading and writing key files,
// loading the folder a broker, worker or client is given with --curve-keys, and putting the keys on a socket.
//
// A key file holds one key in ZeroMQ's Z85 text form (40 characters for 32 bytes) on one line; blank lines and
// lines starting with '#' are ignored. NAME.key holds a secret key (mode 0600: the loader refuses one others can
// read), NAME.pub the matching public key. The folder of --curve-keys:
//
//   DIR/broker.key, DIR/broker.pub     the broker's pair (on the broker); DIR/broker.pub alone on workers and clients
//   DIR/worker.key, DIR/worker.pub     a worker's own pair
//   DIR/client.key, DIR/client.pub     a client's own pair
//   DIR/allowed_workers/*.pub          (broker) the public keys accepted on the worker socket
//   DIR/allowed_clients/*.pub          (broker) the public keys accepted on the client socket
//
// Lives beside the wire schema because the broker and the worker's connection both need it and neither may
// include the other (docs/architecture.md); it links only libzmq, not protobuf.
#pragma once

#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <zmq.hpp>

#include "base/input_error.h"

namespace orcs::net {

/// A key file that is missing, unreadable or malformed, a folder that lacks one, keys that do not fit together, or
/// a libzmq without CURVE. what() is one line naming the file.
class CurveKeyError : public InputError {  // bad input: every program says it and exits 2
 public:
  using InputError::InputError;
};

/// One CURVE key pair, each key in Z85 text.
struct CurveKeyPair {
  std::string public_key;  ///< Z85, 40 characters; given to peers
  std::string secret_key;  ///< Z85, 40 characters; never leaves its owner's machine
};

/// What a worker or a client needs: its own key pair and the broker's public key.
struct CurvePeerKeys {
  CurveKeyPair own;               ///< DIR/ROLE.key and DIR/ROLE.pub (ROLE = worker or client)
  std::string broker_public_key;  ///< DIR/broker.pub, Z85
};

/// Public keys a broker socket accepts: the 32 raw key bytes → the file the key came from (for the log).
using AllowedCurveKeys = std::map<std::string, std::string>;

/// What the broker needs: its own key pair and which public keys each of its two sockets accepts.
struct CurveBrokerKeys {
  CurveKeyPair own;                 ///< DIR/broker.key and DIR/broker.pub
  AllowedCurveKeys allowed_workers;  ///< DIR/allowed_workers/*.pub: accepted on the worker socket only
  AllowedCurveKeys allowed_clients;  ///< DIR/allowed_clients/*.pub: accepted on the client socket only
};

/// Whether this libzmq can do CURVE (Debian's is built with libsodium, so it can).
bool CurveAvailable();
/// Throws CurveKeyError saying so when this libzmq cannot do CURVE.
void RequireCurve();

/// A new random key pair (libsodium's generator, through libzmq).
CurveKeyPair GenerateCurveKeyPair();

/// Writes DIR/NAME.key (mode 0600) and DIR/NAME.pub (mode 0644), making DIR (mode 0700) when missing. NAME is
/// letters, digits, '.', '_' and '-', not starting with '.'. Refuses to overwrite an existing file. Each file is
/// written under a temporary name and renamed, so a half-written key file never exists.
void WriteCurveKeyPair(const std::filesystem::path& dir, const std::string& name, const CurveKeyPair& pair);

/// The Z85 public key in `file`.
std::string ReadCurvePublicKey(const std::filesystem::path& file);
/// DIR/NAME.key and DIR/NAME.pub, checked to be one pair and the secret one to be private.
CurveKeyPair ReadCurveKeyPair(const std::filesystem::path& dir, const std::string& name);

/// The broker's keys from `dir` (see the top of this file). A key in both allowed folders is an error: a key has
/// one role.
CurveBrokerKeys LoadCurveBrokerKeys(const std::filesystem::path& dir);
/// A worker's (role "worker") or a client's (role "client") keys from `dir`.
CurvePeerKeys LoadCurvePeerKeys(const std::filesystem::path& dir, const std::string& role);

/// The ZAP domains the broker's sockets name in their authentication requests: they tell the ZAP handler which
/// socket a peer knocks on.
inline constexpr const char* kWorkerZapDomain = "orcs-workers";
inline constexpr const char* kClientZapDomain = "orcs-clients";

/// Makes `socket` a CURVE server with `own` keys whose peers are checked by the ZAP handler under `zap_domain`.
/// Call before bind().
void MakeCurveServer(zmq::socket_t& socket, const CurveKeyPair& own, const std::string& zap_domain);
/// Makes `socket` a CURVE client of the broker. Call before connect().
void MakeCurveClient(zmq::socket_t& socket, const CurvePeerKeys& keys);

/// The 32 raw bytes of a Z85 key (which must be valid).
std::string CurveKeyBytes(const std::string& z85);
/// The Z85 text of 32 raw key bytes.
std::string CurveKeyText(const std::string& bytes);

}  // namespace orcs::net
