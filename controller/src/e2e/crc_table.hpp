// The byte-at-a-time table of an MSB-first CRC, built at compile time from its polynomial, and the
// register update over it: the one engine of the AUTOSAR CRC routines (crc8_sae_j1850, crc8h2f,
// crc16_ccitt), each of which only names its polynomial, start value and final XOR.
#pragma once

#include <array>
#include <cstdint>
#include <span>

namespace meter::controller::crc_detail {

template <typename T, T Poly>
constexpr std::array<T, 256> msb_first_table() {
  constexpr int kWidth = sizeof(T) * 8;
  constexpr T kTop = static_cast<T>(T{1} << (kWidth - 1));
  std::array<T, 256> table{};
  for (unsigned i = 0; i < 256; ++i) {
    T reg = static_cast<T>(static_cast<T>(i) << (kWidth - 8));
    for (int bit = 0; bit < 8; ++bit) reg = static_cast<T>((reg & kTop) ? (reg << 1) ^ Poly : reg << 1);
    table[i] = reg;
  }
  return table;
}

// An MSB-first CRC of polynomial Poly: its table and the register fed byte by byte.
template <typename T, T Poly>
struct MsbFirstCrc {
  static constexpr std::array<T, 256> kTable = msb_first_table<T, Poly>();
  static T update(T reg, std::span<const std::uint8_t> data) {
    constexpr int kShift = sizeof(T) * 8 - 8;
    for (std::uint8_t b : data) reg = static_cast<T>((reg << 8) ^ kTable[((reg >> kShift) ^ b) & 0xFF]);
    return reg;
  }
};

}  // namespace meter::controller::crc_detail
