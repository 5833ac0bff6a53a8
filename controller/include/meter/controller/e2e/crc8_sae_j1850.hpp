// CRC-8 SAE J1850 (polynomial 0x1D, MSB first), the AUTOSAR CRC library's Crc_CalculateCRC8:
// initial value 0xFF, final XOR 0xFF, check value 0x4B over "123456789". E2E profiles 1 and 11
// and the Chrysler/FCA and Nissan checksums are built on it.
#pragma once

#include <cstdint>
#include <span>

namespace meter::controller {

// The shift register after feeding data into reg (no initial or final XOR): the building block
// that profiles chain over data id and payload.
std::uint8_t crc8_sae_j1850_update(std::uint8_t reg, std::span<const std::uint8_t> data);
// The library's CRC: register 0xFF, then data, then XOR 0xFF.
std::uint8_t crc8_sae_j1850(std::span<const std::uint8_t> data);

}  // namespace meter::controller
