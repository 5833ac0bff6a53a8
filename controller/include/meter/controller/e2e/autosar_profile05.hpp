// AUTOSAR E2E profile 5 (PRS_E2EProtocol): a 16-bit CRC (the library's CRC-16/CCITT-FALSE) over
// the payload without its two CRC bytes, then the 16-bit data id, low byte first; the CRC is
// written little-endian at its offset (by default bytes 0-1, the 8-bit counter in byte 2).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace meter::controller {

// The CRC a profile-5 sender writes at crc_byte (low byte) and crc_byte + 1 (high byte).
std::uint16_t autosar_profile05_crc(std::span<const std::uint8_t> payload, std::size_t crc_byte, std::uint16_t data_id);

}  // namespace meter::controller
