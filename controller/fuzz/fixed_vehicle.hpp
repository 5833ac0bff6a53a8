// The demo vehicle (controller/vehicles/demo) the controller fuzz targets resolve their fuzzed
// input against: its DBC, its mapping, and a model built from both, loaded once per process.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "meter/controller/dbc/database.hpp"
#include "meter/controller/mapping/mapping.hpp"

namespace meter::controller::fuzz {

const Database& demo_dbc();
const Mapping& demo_mapping();

// Input bytes as text, as the readers get a file's contents.
inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

}  // namespace meter::controller::fuzz
