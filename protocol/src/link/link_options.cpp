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

}  // namespace meter::protocol
