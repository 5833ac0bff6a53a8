#include "transport/log.hpp"

#include <algorithm>
#include <cstdio>
#include <map>
#include <mutex>

#include "transport/clock.hpp"
#include "meter/protocol/link.hpp"

namespace meter::protocol {

namespace {
std::mutex g_log_mutex;
LogSink g_sink;

struct Bucket {
  double tokens = 5.0;
  detail::Clock::time_point last{};
  std::uint64_t suppressed = 0;
};
std::map<std::string, Bucket, std::less<>> g_buckets;
}  // namespace

void set_log_sink(LogSink sink) {
  std::lock_guard lock(g_log_mutex);
  g_sink = std::move(sink);
  g_buckets.clear();  // a new sink starts with full budgets: it sees the first lines of each kind
}

namespace detail {

void log_limited(std::string_view key, const std::string& line) {
  std::lock_guard lock(g_log_mutex);
  const auto now = Clock::now();
  auto it = g_buckets.find(key);
  if (it == g_buckets.end()) it = g_buckets.emplace(std::string(key), Bucket{5.0, now, 0}).first;
  Bucket& b = it->second;
  b.tokens = std::min(5.0, b.tokens + std::chrono::duration<double>(now - b.last).count());
  b.last = now;
  if (b.tokens < 1.0) {
    ++b.suppressed;
    return;
  }
  b.tokens -= 1.0;
  std::string text = "meter-protocol: " + line;
  if (b.suppressed > 0) {
    text += " (" + std::to_string(b.suppressed) + " similar message(s) suppressed)";
    b.suppressed = 0;
  }
  if (g_sink) {
    g_sink(text);
  } else {
    std::fprintf(stderr, "%s\n", text.c_str());
  }
}

}  // namespace detail
}  // namespace meter::protocol
