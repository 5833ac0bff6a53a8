// One line of a link's health for a process's exit summary: connections, losses, refusals and the
// frames it refused by class (an attack or a broken peer shows here, counted).
#pragma once

#include <string>

#include "meter/protocol/link.hpp"

namespace meter::protocol {

// "2 connects, 1 loss, 0 handshakes refused, 14 frames refused (mac 3, no-mac 2, crc 9), 1 replay
// dropped, 2 sequence gaps"; a class with no count is left out of the parentheses.
std::string link_stats_text(const LinkStats& stats);

}  // namespace meter::protocol
