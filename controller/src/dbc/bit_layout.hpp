// Where a DBC signal's bits sit in the payload: Intel (LSB-first) and Motorola (MSB-first,
// "sawtooth" numbering) layouts, shared by the codec and the layout checks of the database.
#pragma once

#include <cstdint>

#include "meter/controller/dbc/database.hpp"

namespace meter::controller::dbc_layout {

// Linear big-endian bit index (0 = MSB of byte 0) of a Motorola signal's most significant bit.
inline unsigned motorola_msb_linear(unsigned start) { return (start / 8) * 8 + 7 - (start % 8); }

inline std::uint64_t mask_bits(unsigned len) { return len >= 64 ? ~0ull : ((1ull << len) - 1); }

// Payload bit (byte, bit-in-byte) that holds bit i (0 = LSB) of the signal.
inline void bit_location(const DbcSignal& s, unsigned i, unsigned& byte, unsigned& bit) {
  if (s.little_endian) {
    unsigned p = s.start_bit + i;
    byte = p / 8;
    bit = p % 8;
  } else {
    unsigned lsb = motorola_msb_linear(s.start_bit) + s.length - 1;
    unsigned l = lsb - i;
    byte = l / 8;
    bit = 7 - l % 8;
  }
}

}  // namespace meter::controller::dbc_layout
