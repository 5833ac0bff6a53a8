// Compatibility include for callers not yet moved to meter/engine/package_reader.hpp (the writer
// is meter/convert/package_writer.hpp).
#pragma once

#include "meter/engine/package_reader.hpp"
