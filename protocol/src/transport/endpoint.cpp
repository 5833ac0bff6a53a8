// Endpoint text (unix:/path, tcp:HOST:PORT), the default endpoint and the --link option.
#include <sys/un.h>
#include <unistd.h>

#include <charconv>
#include <cstdlib>
#include <stdexcept>

#include "meter/protocol/endpoint.hpp"

namespace meter::protocol {

Endpoint Endpoint::parse(std::string_view text) {
  const std::string quoted = "endpoint '" + std::string(text) + "': ";
  Endpoint e;
  if (text.starts_with("unix:")) {
    e.kind = Kind::Unix;
    e.path = std::string(text.substr(5));
    if (e.path.empty()) throw std::invalid_argument(quoted + "the unix socket path is empty");
    if (e.path.find('\0') != std::string::npos) throw std::invalid_argument(quoted + "path contains a NUL byte");
    if (e.path.back() == '/') throw std::invalid_argument(quoted + "the unix socket path ends in '/'; expected a file name");
    // A path longer than sun_path is reached through its folder (see transport/unix_address.hpp);
    // only the file name then has to fit.
    const std::size_t name_size = e.path.size() - (e.path.rfind('/') + 1);
    if (e.path.size() >= sizeof(sockaddr_un::sun_path) && name_size > kMaxUnixSocketFileName) {
      throw std::invalid_argument(quoted + "the socket file name is " + std::to_string(name_size) +
                                  " bytes; a path this long (" + std::to_string(e.path.size()) +
                                  " bytes) allows a file name of at most " +
                                  std::to_string(kMaxUnixSocketFileName));
    }
    return e;
  }
  if (text.starts_with("tcp:")) {
    e.kind = Kind::Tcp;
    std::string_view rest = text.substr(4);
    std::string_view port_text;
    if (rest.starts_with("[")) {
      const auto close = rest.find(']');
      if (close == std::string_view::npos) throw std::invalid_argument(quoted + "'[' of an IPv6 host is not closed");
      e.host = std::string(rest.substr(1, close - 1));
      rest = rest.substr(close + 1);
      if (!rest.starts_with(":")) throw std::invalid_argument(quoted + "expected ':PORT' after ']'");
      port_text = rest.substr(1);
    } else {
      const auto colon = rest.rfind(':');
      if (colon == std::string_view::npos) throw std::invalid_argument(quoted + "expected tcp:HOST:PORT");
      e.host = std::string(rest.substr(0, colon));
      if (e.host.find(':') != std::string::npos) {
        throw std::invalid_argument(quoted + "an IPv6 host must be written in brackets: tcp:[::1]:PORT");
      }
      port_text = rest.substr(colon + 1);
    }
    if (e.host.empty()) throw std::invalid_argument(quoted + "the host is empty");
    unsigned port = 0;
    const auto* end = port_text.data() + port_text.size();
    auto [ptr, ec] = std::from_chars(port_text.data(), end, port);
    if (port_text.empty() || ec != std::errc() || ptr != end || port > 65535) {
      throw std::invalid_argument(quoted + "port '" + std::string(port_text) + "' is not a number 0..65535");
    }
    e.port = static_cast<std::uint16_t>(port);
    return e;
  }
  throw std::invalid_argument(quoted + "expected unix:/path/to.sock or tcp:HOST:PORT");
}

std::string Endpoint::to_string() const {
  if (kind == Kind::Unix) return "unix:" + path;
  const bool v6 = host.find(':') != std::string::npos;
  return "tcp:" + (v6 ? "[" + host + "]" : host) + ":" + std::to_string(port);
}

Endpoint default_endpoint() {
  Endpoint e;
  e.kind = Endpoint::Kind::Unix;
  const char* runtime = std::getenv("XDG_RUNTIME_DIR");
  if (runtime != nullptr && runtime[0] == '/') {
    e.path = std::string(runtime) + "/meter.sock";
  } else {
    e.path = "/tmp/meter-" + std::to_string(::getuid()) + "/meter.sock";
  }
  return e;
}

Endpoint endpoint_from_option(std::string_view text) {
  if (text.empty() || text == "default") return default_endpoint();
  return Endpoint::parse(text);
}

}  // namespace meter::protocol
