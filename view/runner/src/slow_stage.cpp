#include "meter/runner/slow_stage.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <thread>

#include "meter/runner/view_error.hpp"

namespace meter::runner {

void SlowStage::in(std::string_view name) const {
  if (delay.count() > 0 && name == stage) std::this_thread::sleep_for(delay);
}

SlowStage parse_slow_stage(const std::string& text, bool overlapped) {
  if (text.empty()) return {};
  const std::string where = "--inject-slow-stage " + text + ": ";
  const auto colon = text.find(':');
  if (colon == std::string::npos) throw ViewError(where + "expected STAGE:MS, e.g. encode:40");
  SlowStage s;
  s.stage = text.substr(0, colon);
  if (std::find(kSlowableStages.begin(), kSlowableStages.end(), s.stage) == kSlowableStages.end()) {
    std::string names;
    for (auto n : kSlowableStages) names += (names.empty() ? "" : ", ") + std::string(n);
    throw ViewError(where + "unknown stage \"" + s.stage + "\" (expected one of " + names + ")");
  }
  const std::string ms_text = text.substr(colon + 1);
  double ms = 0.0;
  const auto [end, ec] = std::from_chars(ms_text.data(), ms_text.data() + ms_text.size(), ms);
  if (ms_text.empty() || ec != std::errc() || end != ms_text.data() + ms_text.size() || !std::isfinite(ms) || ms <= 0.0 ||
      ms > 1000.0)
    throw ViewError(where + "\"" + ms_text + "\" is not a delay in milliseconds (expected a number in (0, 1000])");
  if (!overlapped && (s.stage == "plan" || s.stage == "render"))
    throw ViewError(where + s.stage + " is timed inside the engine's render call in this pipeline: use --pipeline overlapped");
  s.delay = std::chrono::nanoseconds(std::llround(ms * 1e6));
  return s;
}

}  // namespace meter::runner
