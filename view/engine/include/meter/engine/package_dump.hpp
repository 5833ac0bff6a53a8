// The record dump: every stored field of every record of a scene package as text, one
// "path = value" line each, in package order (meter/bridge/package_fields.hpp). Floats are printed
// exactly (%.9g, doubles %.17g); long arrays and texts as their size and an FNV-1a 64 hash.
// `meter-package dump PACKAGE` prints it; two packages with equal dumps hold the same content,
// whatever their framing.
#pragma once

#include <string>

#include "meter/engine/vocabulary.hpp"

namespace meter::engine {

std::string dump_scene(const Scene& scene);

}  // namespace meter::engine
