// One candump -L line for a DBC message with the given physical values: how the end-to-end tests
// write the CAN logs the controller replays. Header-only: only tests that link the controller use it.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>

#include "meter/controller/dbc/codec.hpp"
#include "meter/controller/dbc/database.hpp"
#include "meter/controller/input/candump_line.hpp"

namespace meter::testing {

inline std::string candump_line(const controller::DbcMessage& msg,
                                std::span<const std::pair<std::string_view, double>> values, std::int64_t timestamp_ns) {
  const auto payload = controller::encode(msg, values);
  controller::CanFrame f;
  f.timestamp_ns = timestamp_ns;
  f.id = msg.id;
  f.extended = msg.extended;
  f.len = static_cast<std::uint8_t>(payload.size());
  std::copy(payload.begin(), payload.end(), f.data.begin());
  return controller::format_candump_line(f, "can0");
}

}  // namespace meter::testing
