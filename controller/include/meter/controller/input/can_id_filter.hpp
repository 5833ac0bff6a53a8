// Which frames a SocketCAN kernel filter lets through, as plain data: one entry per message the
// mapping reads, an exact identifier or (J1939) a parameter group under a mask. The rule is the
// kernel's CAN_RAW_FILTER rule, so it is testable here without a socket.
#pragma once

#include <cstdint>
#include <vector>

namespace meter::controller {

struct CanIdFilter {
  std::uint32_t id = 0;
  bool extended = false;
  // Identifier bits that must equal id's; 0 means all of them (an exact identifier).
  std::uint32_t mask = 0;
  friend bool operator==(const CanIdFilter&, const CanIdFilter&) = default;
};

// The parameter group of the 29-bit identifier id29, whatever its priority (bits 26-28) and source
// address (bits 0-7) and, for a PDU1 group (PF < 240), its destination address (bits 8-15).
CanIdFilter j1939_group_filter(std::uint32_t id29);

// The identifier bits a filter compares (its mask, or every bit of its id length).
std::uint32_t effective_mask(const CanIdFilter& filter);

// Does a data frame with this identifier pass? (No filter at all passes everything.)
bool filters_accept(const std::vector<CanIdFilter>& filters, std::uint32_t id, bool extended);

}  // namespace meter::controller
