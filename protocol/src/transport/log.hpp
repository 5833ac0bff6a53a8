// The link's log: every line goes through the sink set with set_log_sink() (link.hpp), or else the
// process's logger (component "link"), rate-limited per kind of event so a peer flooding garbage
// cannot flood the log.
#pragma once

#include <string>
#include <string_view>

#include "meter/protocol/log/log_record.hpp"

namespace meter::protocol::detail {

// Token bucket per event key (RateLimiter): a burst of 5 lines, then one per second; suppressed
// lines are counted and reported with the next line that gets through.
void log_limited(std::string_view key, const std::string& line, LogLevel level = LogLevel::Warning);

}  // namespace meter::protocol::detail
