// Option texts with units: times ("12.5s", "12.5", "250ms") and render sizes ("1280x480").
// Errors (ViewError) name the flag and give examples.
#pragma once

#include <string>
#include <utility>

namespace meter::runner {

// Seconds; a bare number is seconds. Finite and >= 0. `option` names the flag in errors.
double parse_time(const std::string& text, const std::string& option);
// WxH (or WXH), each 16..8192.
std::pair<int, int> parse_size(const std::string& text);

}  // namespace meter::runner
