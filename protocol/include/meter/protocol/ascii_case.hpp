// Comparisons of ASCII text with letter case ignored (keywords of log files, file-name prefixes,
// option values): A-Z and a-z only, every other byte compared as it is, no locale.
#pragma once

#include <string>
#include <string_view>

namespace meter::protocol {

// True when a and b are the same text but for the case of ASCII letters.
bool equals_ignoring_case(std::string_view a, std::string_view b);
// text with its ASCII capitals made small letters.
std::string ascii_lowercase(std::string_view text);
// True when text starts with prefix but for the case of ASCII letters.
bool starts_with_ignoring_case(std::string_view text, std::string_view prefix);

}  // namespace meter::protocol
