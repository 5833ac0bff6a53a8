// AUTOSAR E2E profile 2 (PRS_E2EProtocol): CRC-8H2F over the payload after its first byte (where
// the CRC sits), then one byte of a 16-entry data id list picked by the 4-bit counter (bits 8..11).
// Volkswagen's MQB platform protects its messages this way, each message with its own list.
#pragma once

#include <array>
#include <cstdint>
#include <span>

namespace meter::controller {

using DataIdList = std::array<std::uint8_t, 16>;

// The CRC a profile-2 sender writes in byte 0.
std::uint8_t autosar_profile02_crc(std::span<const std::uint8_t> payload, const DataIdList& data_ids, unsigned counter);

}  // namespace meter::controller
