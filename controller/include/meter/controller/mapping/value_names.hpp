// DBC value names in a mapping: `map = D:127, P:126` and `lit_when = Left, Both` name VAL_ entries
// of the section's DBC sources; at start-up each name becomes the remap entry of the value it
// names (raw -> DBC scaling -> the section's scale/offset), or an error naming the map line, the
// signal and the names its DBC has.
#pragma once

#include <span>

#include "meter/controller/dbc/database.hpp"
#include "meter/controller/mapping/mapping.hpp"
#include "meter/controller/mapping/sources.hpp"

namespace meter::controller {

// Turns every OutputMapping::remap_names entry into remap entries (and clears remap_names).
// Throws MappingError when a name is not in the VAL_ table of every DBC source of its section,
// when the sources disagree on its value, or when the section has no DBC source. Each source is
// resolved against its own input's DBC (the inputs as the model's SourceTable holds them).
void resolve_value_names(Mapping& mapping, std::span<const InputDbc> inputs);
// The same with one input (or none: db null).
void resolve_value_names(Mapping& mapping, const Database* db);

}  // namespace meter::controller
