// Applying a mapping to source values, per catalog signal: each source's newest value is checked
// for freshness (AUTOSAR-COM style first / later timeouts) and against its DBC range, the usable
// ones are combined (first / mean / min / max), converted (scale, offset) and remapped (enum
// values); when every source timed out the output holds, substitutes or reports the timeout.
// Pure functions on plain data: the model feeds them its source table (mapping/sources.hpp) and
// hands the result to conditioning.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "meter/controller/mapping/mapping.hpp"
#include "meter/protocol/catalog.hpp"

namespace meter::controller {

// The newest value of one source as the mapping sees it.
struct SourceReading {
  bool received = false;                // anything received yet
  std::int64_t last_rx_ns = 0;          // when the newest value arrived
  double value = 0;                     // physical value (DBC) or register value (Modbus)
  bool valid = false;                   // usable: decoded valid, or only outside the DBC range
  bool out_of_range = false;            // outside the DBC [min|max]
  double range_min = 0, range_max = 0;  // the DBC range ('out_of_range = clamp' clamps into it)
};

// The source timeouts of one output in nanoseconds, < 0 = none. 'first' applies to a source that
// has not been received since the start; 'later' to the age of the newest value.
struct SourceTimeouts {
  std::int64_t later_ns = -1;
  std::int64_t first_ns = -1;
};

// The timeouts of output m: the mapping's explicit ones, or with 'timeout = auto' derived from the
// slowest source's arrival period (later = 3 periods; first = 10 periods and at least 1 s, for the
// bus to come up). cycle_ms[i] is how often m.sources[i] arrives: the DBC GenMsgCycleTime, for a
// multiplexed signal its page's period (mapping/signal_period.hpp), or the Modbus poll period. Throws MappingError (file, m.line) when 'timeout = auto' meets a source without a cycle.
SourceTimeouts derive_timeouts(const OutputMapping& m, std::span<const std::optional<int>> cycle_ms,
                               const std::string& file);

// The sources of one output after the freshness and range checks.
struct CombinedSources {
  int valid = 0, invalid = 0, timed_out = 0;
  double value = 0;  // the combination of the valid ones (meaningful when valid > 0)
};
// start_ns: when the model started (first timeouts run from there).
CombinedSources combine_sources(const OutputMapping& m, std::span<const SourceReading> sources,
                                const SourceTimeouts& timeouts, std::int64_t t_ns, std::int64_t start_ns);

// Source value -> catalog value: scale and offset, then the exact-value remap (enums).
double convert_value(const OutputMapping& m, double source);

// A catalog signal's value and status, before (mapped) or after (shown) conditioning.
struct OutputValue {
  double value = 0.0;
  protocol::SignalStatus status = protocol::SignalStatus::NotAvailable;
};

// The converted value when a source was usable; otherwise the status says why not: some source
// invalid > some source timed out > nothing received yet. A non-finite result is invalid.
OutputValue mapped_value(const OutputMapping& m, const CombinedSources& sources);

// A timed-out output: 'hold' shows the last good value as valid (when there is one), 'substitute'
// shows the substitute as valid, 'invalid' stays timed out carrying the last good value (or 0).
OutputValue apply_timeout_action(const OutputMapping& m, OutputValue v, std::optional<double> last_good);

// All of the above: the mapped (true, unconditioned) value of output m at t_ns.
OutputValue map_output(const OutputMapping& m, std::span<const SourceReading> sources, const SourceTimeouts& timeouts,
                       std::int64_t t_ns, std::int64_t start_ns, std::optional<double> last_good);

}  // namespace meter::controller
