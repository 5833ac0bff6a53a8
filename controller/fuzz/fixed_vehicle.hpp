// The demo vehicle (controller/vehicles/demo) the controller fuzz targets resolve their fuzzed
// input against: its DBC, its mapping, and a model built from both, loaded once per process; and
// a fuzzed map file's model, as the map and e2e targets build it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

#include "meter/controller/dbc/database.hpp"
#include "meter/controller/input/parsed_log.hpp"
#include "meter/controller/mapping/mapping.hpp"
#include "meter/controller/model/model.hpp"

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
// Builds into model the model of a fuzzed map file ("fuzz.map") against db; false when the map is
// refused. A refusal that does not name the file and line aborts: every map error must say where.
bool model_for_map(std::optional<Model>& model, const Database& db, std::string_view map_text);

// Frame number tick of a fuzz run (at tick x 10 ms): the DBC's messages in turn, the payload read
// from bytes (stride apart per tick; zeros when empty); with short_every > 0 every short_every-th
// frame is a byte shorter than its message.
CanFrame fuzz_frame(const Database& db, std::int64_t tick, std::string_view bytes, std::size_t stride, int short_every = 0);
// Aborts when an output is NaN or infinite: never a silent NaN on the link.
void require_finite_outputs(const Model& model);

// Input bytes as text, as the readers get a file's contents.
inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

}  // namespace meter::controller::fuzz
