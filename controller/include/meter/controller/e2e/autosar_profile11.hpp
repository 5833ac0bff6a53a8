// AUTOSAR E2E profile 11 (PRS_E2EProtocol): profile 1's CRC for CAN (CRC-8 SAE J1850 over the data
// id and the payload, the same bytes in the same order, so a profile-11 receiver reads profile-1
// senders), in the two modes it keeps: Both, and Nibble, where the data id's high nibble also
// travels in the payload (by default bits 12..15, beside the counter in bits 8..11).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "meter/controller/e2e/autosar_profile01.hpp"

namespace meter::controller {

// The CRC a profile-11 sender writes at crc_byte; mode is Both or Nibble (others are refused by
// the configuration before this is called).
std::uint8_t autosar_profile11_crc(std::span<const std::uint8_t> payload, std::size_t crc_byte, std::uint16_t data_id,
                                   DataIdMode mode);
// Nibble mode: the payload's nibble at nibble_bit (little-endian bit number, a multiple of 4)
// equals the low nibble of the data id's high byte. Always true in Both mode.
bool autosar_profile11_nibble_ok(std::span<const std::uint8_t> payload, std::uint16_t data_id, DataIdMode mode,
                                 unsigned nibble_bit = 12);

}  // namespace meter::controller
