// The map file's parser: its text or a file to a Mapping (mapping.hpp, which includes this header).
// Every mistake is a MappingError naming the file, the line and what was expected.
#pragma once

#include <string>
#include <string_view>

namespace meter::controller {

struct Mapping;

Mapping parse_mapping(std::string_view text, const std::string& file = "<map>");
Mapping load_mapping(const std::string& path);

}  // namespace meter::controller
