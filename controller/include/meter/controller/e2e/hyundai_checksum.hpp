// Hyundai / Kia / Genesis on classic CAN (MDPS, TCS, EMS, CLU messages): a 4-bit checksum, 16 minus
// the sum of every payload nibble with the checksum's own nibble counted as 0, modulo 16 (the
// nibble-sum checksum panda's Hyundai safety code documents; its place is the DBC's checksum
// signal). Messages with another rule (WHL_SPD11's bit count) are not covered.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace meter::controller {

// checksum_bit: the little-endian bit number of the checksum nibble's lowest bit (a multiple of 4).
std::uint8_t hyundai_checksum(std::span<const std::uint8_t> payload, unsigned checksum_bit);

}  // namespace meter::controller
