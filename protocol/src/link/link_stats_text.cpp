#include "meter/protocol/link_stats_text.hpp"

#include <utility>

namespace meter::protocol {

std::string link_stats_text(const LinkStats& s) {
  const auto& b = s.bad_frames;
  const std::pair<const char*, std::uint64_t> classes[] = {
      {"mac", b.mac},         {"no-mac", b.no_mac},           {"crc", b.crc},
      {"truncated", b.truncated}, {"version", b.version},    {"bad magic", b.bad_magic},
      {"oversized", b.oversized}, {"unknown type", b.unknown_type}, {"malformed", b.malformed},
  };
  std::string refused;
  for (const auto& [name, count] : classes) {
    if (count != 0) refused += (refused.empty() ? "" : ", ") + std::string(name) + " " + std::to_string(count);
  }
  return std::to_string(s.connects) + " connects, " + std::to_string(s.link_losses) + " losses, " +
         std::to_string(s.handshakes_refused) + " handshakes refused, " + std::to_string(b.total()) +
         " frames refused" + (refused.empty() ? "" : " (" + refused + ")") + ", " +
         std::to_string(s.sequence_replays) + " replays dropped, " + std::to_string(s.sequence_gaps) +
         " sequence gaps";
}

}  // namespace meter::protocol
