#include "meter/controller/mapping/apply.hpp"

#include <algorithm>
#include <cmath>

namespace meter::controller {

using protocol::SignalStatus;

SourceTimeouts derive_timeouts(const OutputMapping& m, std::span<const std::optional<int>> cycle_ms,
                               const std::string& file) {
  SourceTimeouts t;
  if (m.timeout_s) {
    t.later_ns = static_cast<std::int64_t>(*m.timeout_s * 1e9);
  } else if (m.timeout_auto && !cycle_ms.empty() && m.accumulate == Accumulate::None) {
    int cycle = 0;
    for (std::size_t i = 0; i < cycle_ms.size(); ++i) {
      if (!cycle_ms[i])
        throw MappingError(file, m.line, "[" + m.name + "] timeout = auto, but " + m.sources[i] +
                                             " has no GenMsgCycleTime in the DBC; give 'timeout = <seconds>' or 'none'");
      cycle = std::max(cycle, *cycle_ms[i]);
    }
    t.later_ns = static_cast<std::int64_t>(cycle) * 3 * 1000000;
    t.first_ns = std::max<std::int64_t>(1000000000, static_cast<std::int64_t>(cycle) * 10 * 1000000);
  }
  if (m.first_timeout_s) t.first_ns = static_cast<std::int64_t>(*m.first_timeout_s * 1e9);
  else if (t.first_ns < 0 && t.later_ns >= 0) t.first_ns = std::max<std::int64_t>(1000000000, t.later_ns);
  return t;
}

CombinedSources combine_sources(const OutputMapping& m, std::span<const SourceReading> sources,
                                const SourceTimeouts& timeouts, std::int64_t t_ns, std::int64_t start_ns) {
  CombinedSources c;
  for (const SourceReading& s : sources) {
    if (!s.received) {
      if (timeouts.first_ns >= 0 && t_ns - start_ns > timeouts.first_ns) ++c.timed_out;
      continue;
    }
    if (timeouts.later_ns >= 0 && t_ns - s.last_rx_ns > timeouts.later_ns) {
      ++c.timed_out;
      continue;
    }
    double v = s.value;
    bool ok = s.valid;
    if (ok && s.out_of_range) {
      if (m.out_of_range == RangeAction::Invalid) ok = false;
      else if (m.out_of_range == RangeAction::Clamp) v = std::clamp(v, s.range_min, s.range_max);
    }
    if (!ok) {
      ++c.invalid;
      continue;
    }
    if (c.valid == 0) c.value = v;
    else if (m.combine == Combine::Mean) c.value += v;
    else if (m.combine == Combine::Min) c.value = std::min(c.value, v);
    else if (m.combine == Combine::Max) c.value = std::max(c.value, v);
    ++c.valid;
    if (m.combine == Combine::First) break;
  }
  if (c.valid > 0 && m.combine == Combine::Mean) c.value /= c.valid;
  return c;
}

double convert_value(const OutputMapping& m, double source) {
  double value = source * m.scale + m.offset;
  for (const auto& [from, to] : m.remap)
    if (std::fabs(value - from) < 1e-9) return to;
  return m.remap_default.value_or(value);
}

OutputValue mapped_value(const OutputMapping& m, const CombinedSources& sources) {
  OutputValue out;
  if (sources.valid > 0) {
    out.value = convert_value(m, sources.value);
    out.status = std::isfinite(out.value) ? SignalStatus::Valid : SignalStatus::Invalid;
    if (out.status != SignalStatus::Valid) out.value = 0;
  } else if (sources.invalid > 0) {
    out.status = SignalStatus::Invalid;
  } else if (sources.timed_out > 0) {
    out.status = SignalStatus::TimedOut;
  }
  return out;
}

OutputValue apply_timeout_action(const OutputMapping& m, OutputValue v, std::optional<double> last_good) {
  if (v.status != SignalStatus::TimedOut) return v;
  switch (m.on_timeout) {
    case TimeoutAction::Hold:
      if (last_good) v = {*last_good, SignalStatus::Valid};
      break;
    case TimeoutAction::Substitute: v = {m.substitute, SignalStatus::Valid}; break;
    case TimeoutAction::Invalid: v.value = last_good.value_or(0.0); break;
  }
  return v;
}

OutputValue map_output(const OutputMapping& m, std::span<const SourceReading> sources, const SourceTimeouts& timeouts,
                       std::int64_t t_ns, std::int64_t start_ns, std::optional<double> last_good) {
  return apply_timeout_action(m, mapped_value(m, combine_sources(m, sources, timeouts, t_ns, start_ns)), last_good);
}

}  // namespace meter::controller
