// The demo vehicle (controller/vehicles/demo) the controller fuzz targets resolve their fuzzed
// input against: its DBC, its mapping, and a model built from both, loaded once per process.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "meter/controller/dbc/database.hpp"
#include "meter/controller/input/parsed_log.hpp"
#include "meter/controller/mapping/mapping.hpp"

namespace meter::controller::fuzz {

const Database& demo_dbc();
const Mapping& demo_mapping();

// A parsed log as meter-controller replays and decodes it: every frame into the demo vehicle's
// model (DBC decode, mapping, conditioning) and decoded as `meter-controller decode` does. Aborts
// when a frame's length is not legal, or the log counts more frames and bad records than records.
void drive_demo_vehicle(const ParsedLog& log);

// Two frames equal in what a log records: id and its kind, flags, length, the payload bytes
// (none for a remote frame), channel; with_class: an error frame's class and payload too (candump
// keeps them, ASC and BLF do not).
bool same_logged_frame(const CanFrame& a, const CanFrame& b, bool with_class);

// Input bytes as text, as the readers get a file's contents.
inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

}  // namespace meter::controller::fuzz
