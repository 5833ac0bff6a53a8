// candump -L line grammar (can-utils lib.c parse_canframe / snprintf_canframe), re-implemented so
// that bad lines are reported with what was expected instead of being silently skipped.
#include <cstdio>
#include <string>

#include "meter/controller/input/candump_line.hpp"

namespace meter::controller {
namespace {

constexpr std::uint32_t kErrFlag = 0x20000000u;  // CAN_ERR_FLAG as candump prints it

int hexval(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

bool fail(std::string* why, std::string msg) {
  if (why) *why = std::move(msg);
  return false;
}

// Data bytes: pairs of hex digits, optionally separated by '.', up to max bytes.
bool parse_data(std::string_view s, std::size_t& pos, CanFrame& f, std::size_t max, std::string* why) {
  std::size_t n = 0;
  while (pos < s.size() && s[pos] != '_') {
    if (s[pos] == '.') {
      ++pos;
      continue;
    }
    int hi = hexval(s[pos]);
    int lo = pos + 1 < s.size() ? hexval(s[pos + 1]) : -1;
    if (hi < 0 || lo < 0)
      return fail(why, "data byte " + std::to_string(n) + ": expected two hex digits at column " +
                           std::to_string(pos + 1));
    if (n >= max)
      return fail(why, "data: more than " + std::to_string(max) + " bytes");
    f.data[n++] = static_cast<std::uint8_t>(hi * 16 + lo);
    pos += 2;
  }
  f.len = static_cast<std::uint8_t>(n);
  return true;
}

}  // namespace

std::uint8_t can_fd_dlc_to_len(std::uint8_t dlc) {
  static constexpr std::uint8_t k[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 20, 24, 32, 48, 64};
  return k[dlc & 15];
}

std::uint8_t can_fd_len_to_dlc(std::size_t len) {
  std::uint8_t dlc = 0;
  while (dlc < 15 && can_fd_dlc_to_len(dlc) < len) ++dlc;
  return dlc;
}

bool is_valid_fd_len(std::size_t len) {
  return len <= 8 || len == 12 || len == 16 || len == 20 || len == 24 || len == 32 || len == 48 ||
         len == 64;
}

std::optional<CanFrame> parse_frame_text(std::string_view s, std::string* why) {
  CanFrame f;
  std::size_t hash = s.find('#');
  if (hash == std::string_view::npos) {
    fail(why, "frame: expected '<id>#<data>'");
    return std::nullopt;
  }
  if (hash != 3 && hash != 8) {
    fail(why, "id: expected 3 hex digits (standard) or 8 hex digits (extended), got " +
                  std::to_string(hash));
    return std::nullopt;
  }
  std::uint32_t id = 0;
  for (std::size_t i = 0; i < hash; ++i) {
    int v = hexval(s[i]);
    if (v < 0) {
      fail(why, "id: expected a hex digit at column " + std::to_string(i + 1));
      return std::nullopt;
    }
    id = id * 16 + static_cast<std::uint32_t>(v);
  }
  if (hash == 3) {
    if (id > 0x7FF) {
      fail(why, "id: standard id above 0x7FF");
      return std::nullopt;
    }
    f.id = id;
  } else if (id & kErrFlag) {
    f.error = true;
    f.id = id & 0x1FFFFFFFu;
  } else {
    if (id > 0x1FFFFFFF) {
      fail(why, "id: extended id above 0x1FFFFFFF");
      return std::nullopt;
    }
    f.id = id;
    f.extended = true;
  }
  std::size_t pos = hash + 1;
  if (pos < s.size() && s[pos] == '#') {  // CAN FD: ##<flags><data>
    if (f.error) {
      fail(why, "error frames cannot be CAN FD");
      return std::nullopt;
    }
    ++pos;
    int flags = pos < s.size() ? hexval(s[pos]) : -1;
    if (flags < 0) {
      fail(why, "CAN FD: expected one hex flags digit after '##'");
      return std::nullopt;
    }
    f.fd = true;
    f.fd_flags = static_cast<std::uint8_t>(flags);
    ++pos;
    if (!parse_data(s, pos, f, 64, why)) return std::nullopt;
    if (pos != s.size()) {
      fail(why, "CAN FD: unexpected text after data at column " + std::to_string(pos + 1));
      return std::nullopt;
    }
    if (!is_valid_fd_len(f.len)) {
      fail(why, "CAN FD: " + std::to_string(f.len) + " bytes is not a valid FD length");
      return std::nullopt;
    }
    return f;
  }
  if (pos < s.size() && (s[pos] == 'R' || s[pos] == 'r')) {
    f.rtr = true;
    ++pos;
    if (pos < s.size() && s[pos] != '_') {
      int l = hexval(s[pos]);
      if (l < 0 || l > 8) {
        fail(why, "remote frame: expected a length digit 0..8 after 'R'");
        return std::nullopt;
      }
      f.len = static_cast<std::uint8_t>(l);
      ++pos;
    }
  } else {
    if (!parse_data(s, pos, f, 8, why)) return std::nullopt;
  }
  if (pos < s.size() && s[pos] == '_') {  // raw DLC 9..F, only meaningful for len 8
    ++pos;
    int d = pos < s.size() ? hexval(s[pos]) : -1;
    if (d < 9 || f.len != 8) {
      fail(why, "raw DLC: expected '_9'..'_F' after 8 data bytes");
      return std::nullopt;
    }
    f.len8_dlc = static_cast<std::uint8_t>(d);
    ++pos;
  }
  if (pos != s.size()) {
    fail(why, "unexpected text after frame at column " + std::to_string(pos + 1));
    return std::nullopt;
  }
  return f;
}

std::optional<CandumpLine> parse_candump_line(std::string_view line, std::string* why) {
  while (!line.empty() && (line.back() == '\n' || line.back() == '\r' || line.back() == ' ' ||
                           line.back() == '\t'))
    line.remove_suffix(1);
  if (line.empty() || line.front() != '(') {
    fail(why, "timestamp: expected '(seconds.fraction)' at the start of the line");
    return std::nullopt;
  }
  std::size_t close = line.find(')');
  if (close == std::string_view::npos) {
    fail(why, "timestamp: missing ')'");
    return std::nullopt;
  }
  std::string_view ts = line.substr(1, close - 1);
  std::size_t dot = ts.find('.');
  if (dot == std::string_view::npos || dot == 0 || dot + 1 >= ts.size() || ts.size() - dot - 1 > 9 ||
      dot > 12) {
    fail(why, "timestamp: expected '<seconds>.<1..9 fraction digits>'");
    return std::nullopt;
  }
  std::int64_t sec = 0, frac = 0;
  for (std::size_t i = 0; i < dot; ++i) {
    if (ts[i] < '0' || ts[i] > '9') {
      fail(why, "timestamp: expected digits in seconds");
      return std::nullopt;
    }
    sec = sec * 10 + (ts[i] - '0');
  }
  std::size_t fd = ts.size() - dot - 1;
  for (std::size_t i = dot + 1; i < ts.size(); ++i) {
    if (ts[i] < '0' || ts[i] > '9') {
      fail(why, "timestamp: expected digits in fraction");
      return std::nullopt;
    }
    frac = frac * 10 + (ts[i] - '0');
  }
  for (std::size_t i = fd; i < 9; ++i) frac *= 10;
  if (sec > 9000000000LL) {  // nanoseconds since the epoch must fit int64 (year 2255)
    fail(why, "timestamp: seconds beyond 9000000000 do not fit a nanosecond clock");
    return std::nullopt;
  }

  std::string_view rest = line.substr(close + 1);
  auto skip_ws = [&] {
    while (!rest.empty() && (rest.front() == ' ' || rest.front() == '\t')) rest.remove_prefix(1);
  };
  auto token = [&] {
    skip_ws();
    std::size_t n = 0;
    while (n < rest.size() && rest[n] != ' ' && rest[n] != '\t') ++n;
    std::string_view t = rest.substr(0, n);
    rest.remove_prefix(n);
    return t;
  };
  std::string_view iface = token();
  if (iface.empty()) {
    fail(why, "interface: expected an interface name after the timestamp");
    return std::nullopt;
  }
  std::string_view frame_text = token();
  if (frame_text.empty()) {
    fail(why, "frame: expected '<id>#<data>' after the interface name");
    return std::nullopt;
  }
  std::string_view dir = token();
  if (!dir.empty() && dir != "R" && dir != "T") {
    fail(why, "unexpected text after the frame (only a direction flag R/T may follow)");
    return std::nullopt;
  }
  skip_ws();
  if (!rest.empty()) {
    fail(why, "unexpected text at the end of the line");
    return std::nullopt;
  }
  auto f = parse_frame_text(frame_text, why);
  if (!f) return std::nullopt;
  f->timestamp_ns = sec * 1000000000LL + frac;
  return CandumpLine{*f, std::string(iface)};
}

std::string format_candump_line(const CanFrame& f, std::string_view interface) {
  static const char* hex = "0123456789ABCDEF";
  std::string out;
  out.reserve(48 + 2 * f.len);
  char ts[48];
  std::int64_t sec = f.timestamp_ns / 1000000000LL;
  std::int64_t usec = (f.timestamp_ns % 1000000000LL) / 1000;
  std::snprintf(ts, sizeof ts, "(%010lld.%06lld) ", static_cast<long long>(sec),
                static_cast<long long>(usec));
  out += ts;
  out += interface;
  out += ' ';
  char id[16];
  if (f.error)
    std::snprintf(id, sizeof id, "%08X", f.id | kErrFlag);
  else if (f.extended)
    std::snprintf(id, sizeof id, "%08X", f.id);
  else
    std::snprintf(id, sizeof id, "%03X", f.id);
  out += id;
  out += '#';
  if (f.fd) {
    out += '#';
    out += hex[f.fd_flags & 15];
  } else if (f.rtr) {
    out += 'R';
    if (f.len > 0 && f.len <= 8) out += hex[f.len];
  }
  if (!f.rtr) {
    for (std::size_t i = 0; i < f.len; ++i) {
      out += hex[f.data[i] >> 4];
      out += hex[f.data[i] & 15];
    }
  }
  if (!f.fd && f.len == 8 && f.len8_dlc >= 9) {
    out += '_';
    out += hex[f.len8_dlc & 15];
  }
  return out;
}

}  // namespace meter::controller
