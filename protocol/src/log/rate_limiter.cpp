#include "meter/protocol/log/rate_limiter.hpp"

#include <algorithm>

namespace meter::protocol {

std::optional<std::uint64_t> RateLimiter::admit(std::string_view key, double now_s) {
  auto it = buckets_.find(key);
  if (it == buckets_.end()) it = buckets_.emplace(std::string(key), Bucket{kBurst, now_s, 0}).first;
  Bucket& b = it->second;
  b.tokens = std::min(kBurst, b.tokens + (now_s - b.last_s) * kPerSecond);
  b.last_s = now_s;
  if (b.tokens < 1.0) {
    ++b.suppressed;
    return std::nullopt;
  }
  b.tokens -= 1.0;
  const std::uint64_t suppressed = b.suppressed;
  b.suppressed = 0;
  return suppressed;
}

std::string suppressed_note(std::uint64_t suppressed) {
  return suppressed == 0 ? std::string() : " (" + std::to_string(suppressed) + " similar message(s) suppressed)";
}

}  // namespace meter::protocol
