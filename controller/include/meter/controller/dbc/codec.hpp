// DBC codec: payload bytes -> raw bits -> physical values (decode) and back (encode), with the
// per-signal status (short frame, out of range, J1939 not-available / error patterns, not finite).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "meter/controller/dbc/database.hpp"

namespace meter::controller {

enum class DecodeStatus : std::uint8_t {
  Valid,
  ShortFrame,    // the frame is shorter than the bytes this signal needs
  OutOfRange,    // outside the DBC [min|max]
  NotAvailable,  // J1939 'not available' raw pattern (all ones)
  ErrorValue,    // J1939 'error' raw pattern
  NotFinite,     // float signal carried NaN or Inf: never sent as a number
};
std::string_view to_string(DecodeStatus status);

struct DecodedSignal {
  int signal = -1;  // index into DbcMessage::signals
  std::uint64_t raw = 0;     // raw bits as unsigned (two's complement for signed)
  double physical = 0.0;     // 0 when status is NotFinite, or ShortFrame and not finite
  DecodeStatus status = DecodeStatus::Valid;
  std::int64_t raw_signed() const { return static_cast<std::int64_t>(raw); }
};

// Raw bits of one signal (sign-extended into the uint64 when signed). Payload shorter than needed:
// missing bytes read as zero (decode() reports ShortFrame for them).
std::uint64_t extract_raw(const DbcSignal& s, std::span<const std::uint8_t> payload);
void insert_raw(const DbcSignal& s, std::uint64_t raw, std::span<std::uint8_t> payload);
// Physical value of raw bits (float types reinterpret the bits).
double raw_to_physical(const DbcSignal& s, std::uint64_t raw);

// Decodes every present signal of the message (inactive multiplexed signals are skipped).
// Appends to out (cleared first); returns the number decoded.
std::size_t decode(const DbcMessage& m, std::span<const std::uint8_t> payload,
                   std::vector<DecodedSignal>& out);

// The DBC signal a decoded value belongs to.
inline const DbcSignal& signal_of(const DbcMessage& m, const DecodedSignal& d) {
  return m.signals[static_cast<std::size_t>(d.signal)];
}
// The decoded value of the signal called 'name', or null when decode() did not produce it.
const DecodedSignal* find_decoded(const DbcMessage& m, std::span<const DecodedSignal> decoded, std::string_view name);

// Encoder: physical values by signal name -> payload of m.size bytes. Signals not listed are 0 raw
// (multiplexed signals whose switch value does not select them are left out). Values are rounded
// to the nearest raw step; a value that does not fit the raw width throws std::out_of_range naming
// the signal. Unknown signal names throw std::invalid_argument.
std::vector<std::uint8_t> encode(const DbcMessage& m,
                                 std::span<const std::pair<std::string_view, double>> values);
// Raw for a physical value (rounded, range-checked against the bit width).
std::uint64_t physical_to_raw(const DbcSignal& s, double physical);

}  // namespace meter::controller
