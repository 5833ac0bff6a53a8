// How one end of the link behaves: heartbeat period and loss detection, peer allow-list,
// reconnect backoff, its name in HELLO and log lines.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "meter/protocol/endpoint.hpp"

namespace meter::protocol {

struct LinkOptions {
  std::chrono::milliseconds heartbeat_period{100};
  int missed_heartbeats_for_loss = 3;     // silence for this many periods = link lost
  std::vector<uid_t> allowed_uids;        // empty = only our own uid (Unix sockets, SO_PEERCRED)
  std::chrono::milliseconds reconnect_min{50}, reconnect_max{2000};  // Subscriber backoff
  std::string name;                       // sent in HELLO, used in log lines ("meter-view")
  std::size_t max_peers = 16;             // Publisher: connections beyond this get CLOSE and are dropped
  // The catalog hash announced in HELLO. Empty = the hash of the catalog in use. Only tools and
  // tests that deliberately emulate another build set it.
  std::optional<std::uint64_t> catalog_hash_override;
  // Subscriber: when the publisher's catalog differs from ours, ask for it (HELLO flag) and use
  // it: it becomes this process's active catalog and the table is rebuilt on it. false: such a
  // link is refused with a message naming both catalog files.
  bool take_peer_catalog = false;
  // The link key file (meter/protocol/key_file.hpp): every frame then carries a MAC and the peer
  // must hold the key this end names in HELLO. Empty: no MAC, which a TCP endpoint refuses unless
  // `insecure_link` says a lab allows it (each connection's log lines then say UNAUTHENTICATED).
  std::string key_file;
  bool insecure_link = false;
};

// The help of the two options every program on the link offers (--key-file FILE, --insecure-link).
inline constexpr const char* kKeyFileHelp =
    "link key file (mode 0600; docs/security.md): every frame carries a MAC, the peer must hold the key "
    "named in HELLO; re-read when it changes";
inline constexpr const char* kInsecureLinkHelp =
    "lab only: allow a TCP link without a key file (anyone who can reach the port can drive the display); "
    "every connection's log lines say UNAUTHENTICATED";

// "" if `options` may be used on `where`, else why not: a TCP endpoint without a key file and
// without insecure_link (anyone who can reach the port could drive the telltales).
std::string link_security_error(const Endpoint& where, const LinkOptions& options);

// The options meter-controller and meter-view both derive from their --link-timeout (the silence
// after which the link counts as lost): loss after 3 missed heartbeats, so a heartbeat every third
// of the timeout, and never more often than every 10 ms. `name` goes into HELLO and log lines.
LinkOptions link_options(std::string name, std::chrono::milliseconds link_timeout);

}  // namespace meter::protocol
