// AUTOSAR E2E profile 1 (E2E Protocol Specification, PRS_E2EProtocol): an 8-bit CRC-8 SAE J1850
// over the data id and the payload, and a 4-bit counter (0..14, 15 is never sent). The CRC chains
// Crc_CalculateCRC8 from start value 0xFF with a final XOR 0xFF, so in effect the register starts
// at 0x00 and nothing is XORed at the end.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace meter::controller {

// Which bytes of the 16-bit data id the CRC covers (E2E_P01DataIDMode).
enum class DataIdMode : std::uint8_t {
  Both,         // low byte, then high byte
  Alternating,  // low byte when the counter is even, high byte when it is odd
  Low,          // low byte only (the high byte is 0)
  Nibble,       // low byte, then 0x00; the high byte's low nibble travels in the payload
};

// The CRC a profile-1 sender writes at crc_byte: data id bytes by mode, then every payload byte
// except crc_byte, in order. counter selects the byte in Alternating mode.
std::uint8_t autosar_profile01_crc(std::span<const std::uint8_t> payload, std::size_t crc_byte, std::uint16_t data_id,
                                   DataIdMode mode, unsigned counter);

}  // namespace meter::controller
