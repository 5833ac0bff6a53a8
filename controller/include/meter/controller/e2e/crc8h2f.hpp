// CRC-8H2F (polynomial 0x2F, MSB first), the AUTOSAR CRC library's Crc_CalculateCRC8H2F: initial
// value 0xFF, final XOR 0xFF, check value 0xDF over "123456789". E2E profile 2 (and with it the
// Volkswagen MQB checksum) is built on it.
#pragma once

#include <cstdint>
#include <span>

namespace meter::controller {

// The shift register after feeding data into reg (no initial or final XOR).
std::uint8_t crc8h2f_update(std::uint8_t reg, std::span<const std::uint8_t> data);
// The library's CRC: register 0xFF, then data, then XOR 0xFF.
std::uint8_t crc8h2f(std::span<const std::uint8_t> data);

}  // namespace meter::controller
