// Whether a signal's state changed: the one rule both sides of the link apply (the controller's
// Model when it lists a tick's changed outputs, the SignalTable of the Publisher and the
// Subscriber when they store a value).
//
// A value changes when its bits change. The link carries each value's 64 IEEE-754 bits as they
// are, and the view draws what arrives: -0.0 after 0.0 prints "-0" on a readout, so it is a change
// the view must receive; and the comparison stays exact (no tolerance) and total (a value always
// equals itself, which a NaN compared with != would not; the wire refuses non-finite values
// anyway). The status is compared as well: a value that keeps its number but times out changed.
#pragma once

#include <bit>
#include <cstdint>

#include "meter/protocol/catalog.hpp"

namespace meter::protocol {

constexpr bool value_changed(double before, double after) {
  return std::bit_cast<std::uint64_t>(before) != std::bit_cast<std::uint64_t>(after);
}

constexpr bool signal_changed(double before, SignalStatus before_status, double after, SignalStatus after_status) {
  return value_changed(before, after) || before_status != after_status;
}

}  // namespace meter::protocol
