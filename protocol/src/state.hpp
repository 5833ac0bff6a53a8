// The signal table both ends keep: one SignalState per catalog entry, indexed by catalog position.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "meter/protocol/link.hpp"

namespace meter::protocol::detail {

struct SignalTable {
  std::vector<SignalState> states = std::vector<SignalState>(catalog().size());

  static std::size_t index_or_throw(SignalId id, const char* who);       // std::invalid_argument
  static std::size_t index_or_out_of_range(SignalId id);                 // std::out_of_range
  // Stores the value; true if anything observable changed (value bits, status or text).
  // `text` null = keep the current text.
  bool assign(std::size_t index, double value, SignalStatus status, const std::string* text);
};

}  // namespace meter::protocol::detail
