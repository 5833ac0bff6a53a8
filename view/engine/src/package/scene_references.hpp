// The references between a package's sections (node -> mesh, draw -> program, group -> draws,
// integrity region -> binding, ...), checked once every section is read, so a package that passed
// the checksum but was written by a buggy converter still never indexes out of range at runtime.
#pragma once

#include <string>

#include "meter/engine/vocabulary.hpp"

namespace meter::engine {

// Throws SceneError "<origin>: corrupt package: <what>".
void check_references(const Scene& s, const std::string& origin);

// Parses the stored scene config text into s.config (and s.ambient), then checks the integrity
// regions' bindings against it. Throws SceneError naming `origin`.
void load_config(Scene& s, const std::string& origin);

}  // namespace meter::engine
