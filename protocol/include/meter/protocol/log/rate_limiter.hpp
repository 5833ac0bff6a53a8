// Per kind of event, a token bucket: a burst of 5 lines, then one per second; suppressed lines are
// counted and reported with the next line that gets through. Pure: the caller gives the time.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>

namespace meter::protocol {

class RateLimiter {
 public:
  // Whether a line of kind `key` at `now_s` (any monotonic seconds) is written; when it is, the
  // number of lines of that kind suppressed since the last one written (0: none), else nothing.
  std::optional<std::uint64_t> admit(std::string_view key, double now_s);
  void clear() { buckets_.clear(); }

  static constexpr double kBurst = 5.0;        // lines of a kind written back to back
  static constexpr double kPerSecond = 1.0;    // then this many a second

 private:
  struct Bucket {
    double tokens = kBurst;
    double last_s = 0;
    std::uint64_t suppressed = 0;
  };
  std::map<std::string, Bucket, std::less<>> buckets_;
};

// " (N similar message(s) suppressed)" for N > 0, else empty: the tail the line gets.
std::string suppressed_note(std::uint64_t suppressed);

}  // namespace meter::protocol
