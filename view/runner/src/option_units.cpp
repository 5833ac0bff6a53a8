#include "meter/runner/option_units.hpp"

#include <cmath>
#include <cstdio>

#include "meter/runner/view_error.hpp"

namespace meter::runner {

double parse_time(const std::string& text, const std::string& option) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    throw ViewError(option + ": \"" + text + "\" is not a time (examples: 12.5s, 250ms)");
  }
  const std::string unit = text.substr(used);
  if (unit == "ms") v /= 1000.0;
  else if (!unit.empty() && unit != "s") throw ViewError(option + ": unknown unit \"" + unit + "\" (use s or ms)");
  if (!std::isfinite(v) || v < 0) throw ViewError(option + ": time must be finite and >= 0");
  return v;
}

std::pair<int, int> parse_size(const std::string& text) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w < 16 || h < 16 ||
      w > 8192 || h > 8192) {
    throw ViewError("--size: expected WxH with 16..8192 each, got \"" + text + "\"");
  }
  return {w, h};
}

}  // namespace meter::runner
