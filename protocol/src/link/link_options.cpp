#include "meter/protocol/link_options.hpp"

#include <algorithm>
#include <utility>

namespace meter::protocol {

LinkOptions link_options(std::string name, std::chrono::milliseconds link_timeout) {
  constexpr std::chrono::milliseconds kFastestHeartbeat{10};
  LinkOptions options;
  options.name = std::move(name);
  options.missed_heartbeats_for_loss = 3;
  options.heartbeat_period = std::max(kFastestHeartbeat, link_timeout / options.missed_heartbeats_for_loss);
  return options;
}

std::string link_security_error(const Endpoint& where, const LinkOptions& options) {
  if (where.kind != Endpoint::Kind::Tcp || !options.key_file.empty() || options.insecure_link) return {};
  return "an unauthenticated TCP link on " + where.to_string() +
         " is refused: anyone who can reach the port could drive the telltales. Give a key file "
         "(--key-file FILE, docs/security.md), or --insecure-link for a lab";
}

}  // namespace meter::protocol
