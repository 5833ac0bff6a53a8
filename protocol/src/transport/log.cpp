#include "transport/log.hpp"

#include <mutex>

#include "meter/protocol/link.hpp"
#include "meter/protocol/log/logger.hpp"
#include "meter/protocol/log/rate_limiter.hpp"
#include "transport/clock.hpp"

namespace meter::protocol {

namespace {
std::mutex g_log_mutex;
LogSink g_sink;
RateLimiter g_limiter;
}  // namespace

void set_log_sink(LogSink sink) {
  std::lock_guard lock(g_log_mutex);
  g_sink = std::move(sink);
  g_limiter.clear();  // a new sink starts with full budgets: it sees the first lines of each kind
}

namespace detail {

void log_limited(std::string_view key, const std::string& line, LogLevel level) {
  std::lock_guard lock(g_log_mutex);
  const double now_s = std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
  const auto suppressed = g_limiter.admit(key, now_s);
  if (!suppressed) return;
  if (g_sink) {
    g_sink("meter-protocol: " + line + suppressed_note(*suppressed));
    return;
  }
  LogRecord r;
  r.level = level;
  r.component = "link";
  r.prefix = "meter-protocol: ";
  r.message = line + suppressed_note(*suppressed);
  r.fields.push_back(log_field("event", std::string(key)));
  if (*suppressed > 0) r.fields.push_back(log_field("suppressed", static_cast<std::int64_t>(*suppressed)));
  write_log(std::move(r));
}

}  // namespace detail
}  // namespace meter::protocol
