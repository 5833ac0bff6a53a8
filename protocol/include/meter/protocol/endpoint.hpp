// Where the link's two ends meet: a Unix socket path or a TCP host and port.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace meter::protocol {

inline constexpr std::size_t kMaxUnixSocketFileName = 80;

// Where the Publisher listens and the Subscriber connects.
//   "unix:/path/to.sock"   Unix domain socket, SOCK_SEQPACKET (the default on one machine)
//   "tcp:HOST:PORT"        TCP stream; HOST is a name, an IPv4 address or "[IPv6]"; PORT 0 asks the
//                          Publisher for an ephemeral port (see Publisher::endpoint()).
//   A Unix socket path may be of any length; when it is longer than the kernel's sun_path (107
//   bytes) only its file name has to stay within kMaxUnixSocketFileName.
struct Endpoint {
  enum class Kind { Unix, Tcp } kind = Kind::Unix;
  std::string path;          // Unix only
  std::string host;          // Tcp only
  std::uint16_t port = 0;    // Tcp only
  static Endpoint parse(std::string_view text);  // throws std::invalid_argument with a clear message
  std::string to_string() const;
  bool operator==(const Endpoint&) const = default;
};

// unix:$XDG_RUNTIME_DIR/meter.sock, or unix:/tmp/meter-<uid>/meter.sock when XDG_RUNTIME_DIR is
// unset (the Publisher creates that directory with mode 0700).
Endpoint default_endpoint();

// The endpoint a --link command-line option names: "default" or "" is default_endpoint(),
// anything else goes through Endpoint::parse (and its std::invalid_argument).
Endpoint endpoint_from_option(std::string_view text);

}  // namespace meter::protocol
