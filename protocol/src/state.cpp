#include "state.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <stdexcept>

#include "meter/protocol/wire.hpp"

namespace meter::protocol::detail {

std::size_t SignalTable::index_or_throw(SignalId id, const char* who) {
  const SignalInfo* info = find_signal(id);
  if (info == nullptr) {
    throw std::invalid_argument(std::string(who) + ": signal id " + std::to_string(id) +
                                " is not in the catalog (protocol/src/catalog.cpp)");
  }
  return static_cast<std::size_t>(info - catalog().data());
}

std::size_t SignalTable::index_or_out_of_range(SignalId id) {
  const SignalInfo* info = find_signal(id);
  if (info == nullptr) {
    throw std::out_of_range("signal id " + std::to_string(id) + " is not in the catalog");
  }
  return static_cast<std::size_t>(info - catalog().data());
}

bool SignalTable::assign(std::size_t index, double value, SignalStatus status, const std::string* text) {
  SignalState& s = states[index];
  // Compare bits, not values: -0.0 vs 0.0 is a change a display may care about, and it keeps the
  // comparison exact.
  bool changed = std::bit_cast<std::uint64_t>(s.value) != std::bit_cast<std::uint64_t>(value) || s.status != status;
  s.value = value;
  s.status = status;
  if (text != nullptr && *text != s.text) {
    s.text = *text;
    changed = true;
  }
  return changed;
}

}  // namespace meter::protocol::detail
