// The byte-at-a-time table of an MSB-first CRC, built at compile time from its polynomial: the
// shared engine of the AUTOSAR CRC routines (crc8_sae_j1850, crc8h2f, crc16_ccitt).
#pragma once

#include <array>
#include <cstdint>

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

}  // namespace meter::controller::crc_detail
