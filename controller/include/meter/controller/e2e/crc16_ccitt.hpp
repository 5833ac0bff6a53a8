// CRC-16 CCITT (polynomial 0x1021, MSB first). The AUTOSAR CRC library's Crc_CalculateCRC16 is
// CRC-16/CCITT-FALSE: initial value 0xFFFF, no final XOR, check value 0x29B1 over "123456789".
// E2E profile 5 is built on it; the Hyundai/Kia CAN FD checksum runs the same register from 0.
#pragma once

#include <cstdint>
#include <span>

namespace meter::controller {

// The shift register after feeding data into reg.
std::uint16_t crc16_ccitt_update(std::uint16_t reg, std::span<const std::uint8_t> data);
// The library's CRC16: register 0xFFFF, then data.
std::uint16_t crc16_ccitt_false(std::span<const std::uint8_t> data);

}  // namespace meter::controller
