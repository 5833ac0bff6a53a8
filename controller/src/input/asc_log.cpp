// Vector ASC logs read line by line: the header settles the number base and the time mode, a
// trigger block's date the clock, and each event line is a frame, an event passed over, or a bad
// line saying what was expected.
#include "meter/controller/input/asc_log.hpp"
#include "meter/controller/input/asc_log_writer.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "meter/controller/input/candump_line.hpp"
#include "meter/controller/input/log_fields.hpp"
#include "meter/controller/input/log_lines.hpp"
#include "meter/protocol/ascii_case.hpp"

namespace meter::controller {
namespace {

using protocol::equals_ignoring_case;

// Events that hold no CAN frame, passed over: the measurement's start, statistics, chip status,
// system and environment variables, J1939 transport, other buses.
constexpr std::array<std::string_view, 16> kAscOtherEvents = {
    "Start", "Stop", "SV:", "EnvVar:", "CAN", "Statistic:", "Status:", "J1939TP", "Li", "LIN", "FR", "ETH", "TFS:",
    "Trigger", "Log", "Chip"};

bool asc_other_event(std::string_view word) {
  return std::any_of(kAscOtherEvents.begin(), kAscOtherEvents.end(), [&](std::string_view k) { return equals_ignoring_case(k, word); });
}

// "Sep 12 03:15:14.717 pm 2021", a weekday before it or not, 12- or 24-hour clock, English or
// German month names.
std::optional<std::int64_t> asc_date(std::span<const std::string_view> f) {
  static constexpr std::array<std::string_view, 16> kMonths = {"jan", "feb", "mar", "apr", "may", "jun", "jul", "aug",
                                                               "sep", "oct", "nov", "dec", "mär", "mai", "okt", "dez"};
  static constexpr int kMonthNumber[16] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 3, 5, 10, 12};
  auto month_of = [&](std::string_view w) {
    for (std::size_t i = 0; i < kMonths.size(); ++i)
      if (w.size() >= 3 && protocol::starts_with_ignoring_case(w, kMonths[i])) return kMonthNumber[i];
    return 0;
  };
  if (!f.empty() && month_of(f[0]) == 0) f = f.subspan(1);  // the weekday
  if (f.size() != 4 && f.size() != 5) return std::nullopt;
  const int month = month_of(f[0]);
  const auto day = parse_log_number(f[1], 10, 31), year = parse_log_number(f[f.size() - 1], 10, 9999);
  const std::string_view clock = f[2];
  if (!month || !day || !year || clock.size() < 8 || clock[2] != ':' || clock[5] != ':') return std::nullopt;
  auto hour = parse_log_number(clock.substr(0, 2), 10, 23), minute = parse_log_number(clock.substr(3, 2), 10, 59);
  const auto seconds = parse_log_time(clock.substr(6), 1000000000LL);
  if (!hour || !minute || !seconds) return std::nullopt;
  if (f.size() == 5) {  // 12-hour clock
    const bool pm = equals_ignoring_case(f[3], "pm");
    if (!pm && !equals_ignoring_case(f[3], "am")) return std::nullopt;
    if (*hour == 0 || *hour > 12) return std::nullopt;
    *hour = *hour % 12 + (pm ? 12 : 0);
  }
  return local_time_ns(static_cast<int>(*year), month, static_cast<int>(*day), static_cast<int>(*hour),
                       static_cast<int>(*minute), static_cast<int>(*seconds / 1000000000LL), *seconds % 1000000000LL);
}

class AscReader {
 public:
  explicit AscReader(ParsedLog& window) : log(window) {}
  void line(std::string_view t) {
    ++log.lines;
    if (t.empty()) return;
    split_log_fields(t, f_);
    const std::string_view w = f_[0];
    if (w.substr(0, 2) == "//") return;
    if (w[0] >= '0' && w[0] <= '9') return event();
    if (equals_ignoring_case(w, "date")) return date(std::span(f_).subspan(1), false);
    if (equals_ignoring_case(w, "base")) return base();
    if (equals_ignoring_case(w, "internal") || (equals_ignoring_case(w, "no") && f_.size() > 1 && equals_ignoring_case(f_[1], "internal"))) return;
    if ((equals_ignoring_case(w, "begin") || equals_ignoring_case(w, "end")) && f_.size() > 1 && equals_ignoring_case(f_[1], "triggerblock")) {
      if (equals_ignoring_case(w, "begin") && f_.size() > 2) date(std::span(f_).subspan(2), true);
      return;
    }
    bad("unknown keyword '" + std::string(w.substr(0, 40)) +
        "': expected date, base, internal events logged, Begin/End TriggerBlock, a // comment or an event '<seconds> ...'");
  }
  ParsedLog& log;

 private:
  std::vector<std::string_view> f_;
  int base_ = 16;
  bool relative_ = false;
  bool in_block_ = false;  // a trigger block's date is the clock, not the file's
  std::int64_t start_ns_ = 0, last_ns_ = 0;

  void bad(std::string why) { log.bad_lines.push_back({log.lines, std::move(why)}); }

  bool number_at(std::size_t k, int base, std::uint32_t max, std::uint32_t& v) const {
    const auto r = k < f_.size() ? parse_log_number(f_[k], base, max) : std::nullopt;
    if (r) v = *r;
    return r.has_value();
  }

  void date(std::span<const std::string_view> fields, bool block) {
    const auto t = asc_date(fields);
    if (!t) return bad("date: expected '[weekday] month day hh:mm:ss[.fff] [am|pm] year'");
    if (block || !in_block_) start_ns_ = *t, last_ns_ = *t;
    in_block_ |= block;
  }

  void base() {
    if (f_.size() < 2 || (!equals_ignoring_case(f_[1], "hex") && !equals_ignoring_case(f_[1], "dec")))
      return bad("base: expected 'base hex|dec [timestamps absolute|relative]'");
    base_ = equals_ignoring_case(f_[1], "hex") ? 16 : 10;
    if (f_.size() >= 4 && equals_ignoring_case(f_[2], "timestamps")) relative_ = equals_ignoring_case(f_[3], "relative");
  }

  void event() {
    const auto t = parse_log_time(f_[0], 1000000000LL);
    if (!t) return bad("time: expected '<seconds>.<fraction>' at the start of an event");
    std::int64_t ts = 0;
    if (__builtin_add_overflow(relative_ ? last_ns_ : start_ns_, *t, &ts)) return bad("time: beyond the nanosecond clock (year 2262)");
    last_ns_ = ts;
    if (f_.size() < 2) return bad("event: expected a channel, CANFD or an event name after the time");
    CanFrame fr;
    fr.timestamp_ns = ts;
    if (equals_ignoring_case(f_[1], "CANFD")) return fd(fr);
    if (f_[1][0] < '0' || f_[1][0] > '9') {
      if (asc_other_event(f_[1])) return void(++log.skipped);
      return bad("unknown event '" + std::string(f_[1].substr(0, 40)) + "': expected a channel number, CANFD or a known event");
    }
    if (!channel(f_[1], fr)) return;
    if (f_.size() > 2 && equals_ignoring_case(f_[2], "ErrorFrame")) return error(fr);
    if (f_.size() < 5 || (f_[3] != "Rx" && f_[3] != "Tx")) {
      if (f_.size() > 2 && asc_other_event(f_[2])) return void(++log.skipped);
      return bad("frame: expected '<channel> <id>[x] Rx|Tx d <dlc> <bytes>' or 'r [<dlc>]'");
    }
    if (!id(f_[2], fr)) return;
    if (equals_ignoring_case(f_[4], "r")) return remote(fr);
    if (!equals_ignoring_case(f_[4], "d")) return bad("frame: expected 'd' (data) or 'r' (remote) after Rx|Tx");
    const auto dlc = f_.size() > 5 ? parse_log_number(f_[5], base_, 15) : std::nullopt;
    if (!dlc) return bad("DLC: expected a number 0..15 after 'd'");
    fr.len = static_cast<std::uint8_t>(std::min<std::uint32_t>(*dlc, 8));
    if (*dlc > 8) fr.len8_dlc = static_cast<std::uint8_t>(*dlc);
    if (data(6, fr) && tail_ok(6 + fr.len)) log.frames.push_back(fr);
  }

  bool channel(std::string_view text, CanFrame& fr) {
    const auto c = parse_log_number(text, 10, 255);
    if (!c || *c == 0) return bad("channel: expected a number 1..255"), false;
    fr.channel = static_cast<std::uint8_t>(*c);
    return true;
  }

  bool id(std::string_view text, CanFrame& fr) {
    fr.extended = !text.empty() && (text.back() == 'x' || text.back() == 'X');
    if (fr.extended) text.remove_suffix(1);
    const auto v = parse_log_number(text, base_, fr.extended ? 0x1FFFFFFFu : 0x7FFu);
    if (!v) return bad(std::string("id: expected a ") + (base_ == 16 ? "hex" : "decimal") + " identifier up to " +
                       (fr.extended ? "1FFFFFFF (extended, 'x')" : "7FF (standard)")), false;
    fr.id = *v;
    return true;
  }

  bool data(std::size_t first, CanFrame& fr) {
    if (f_.size() < first + fr.len) return bad("data: expected " + std::to_string(fr.len) + " byte(s), got " + std::to_string(f_.size() - std::min(f_.size(), first))), false;
    for (std::size_t i = 0; i < fr.len; ++i) {
      const auto b = parse_log_number(f_[first + i], base_, 255);
      if (!b) return bad("data byte " + std::to_string(i) + ": expected a number 0..255 in base " + std::to_string(base_)), false;
      fr.data[i] = static_cast<std::uint8_t>(*b);
    }
    return true;
  }

  // What may follow a classic frame's bytes: Vector's "Length = ... BitCount = ... ID = ..." notes.
  bool tail_ok(std::size_t from) {
    if (from >= f_.size() || equals_ignoring_case(f_[from], "Length") || equals_ignoring_case(f_[from], "BitCount") || equals_ignoring_case(f_[from], "ID")) return true;
    return bad("frame: unexpected '" + std::string(f_[from].substr(0, 20)) + "' after the data bytes (more bytes than the DLC?)"), false;
  }

  void remote(CanFrame& fr) {
    fr.rtr = true;
    std::size_t next = 5;
    if (f_.size() > 5 && !equals_ignoring_case(f_[5], "Length") && !equals_ignoring_case(f_[5], "BitCount")) {
      const auto dlc = parse_log_number(f_[5], base_, 15);
      if (!dlc) return bad("remote frame: expected its DLC 0..15 after 'r'");
      fr.len = static_cast<std::uint8_t>(std::min<std::uint32_t>(*dlc, 8));
      next = 6;
    }
    if (tail_ok(next)) log.frames.push_back(fr);
  }

  void error(CanFrame& fr) {
    fr.error = true;  // ASC says no more than that: no error class, id 0
    log.frames.push_back(fr);
  }

  // <time> CANFD <channel> Rx|Tx <id>[x] [<name>] <brs> <esi> <dlc> <length> <bytes> [<duration>
  // <bit length> <flags> <crc> ...]; flags bit 12 (EDL) clear: a classic frame, bit 4: remote.
  void fd(CanFrame& fr) {
    if (f_.size() < 4) return bad("CANFD: expected '<channel> Rx|Tx <id>' after CANFD");
    if (!channel(f_[2], fr)) return;
    if (f_.size() > 4 && equals_ignoring_case(f_[4], "ErrorFrame")) return error(fr);
    if (f_.size() < 9 || (f_[3] != "Rx" && f_[3] != "Tx"))
      return bad("CANFD: expected '<channel> Rx|Tx <id> [name] <brs> <esi> <dlc> <length> <bytes>'");
    if (!id(f_[4], fr)) return;
    std::size_t i = (f_[5][0] >= '0' && f_[5][0] <= '9') ? 5 : 6;  // a symbolic name or not
    std::uint32_t brs = 0, esi = 0, dlc = 0, length = 0;
    if (!number_at(i, 10, 1, brs) || !number_at(i + 1, 10, 1, esi) || !number_at(i + 2, 16, 15, dlc) || !number_at(i + 3, 10, 64, length))
      return bad("CANFD: expected <brs 0|1> <esi 0|1> <dlc hex> <data length 0..64>");
    if (!is_valid_fd_len(length) || can_fd_dlc_to_len(static_cast<std::uint8_t>(dlc)) != length)
      return bad("CANFD: data length " + std::to_string(length) + " does not match DLC " + std::to_string(dlc));
    fr.fd = true;
    fr.fd_flags = static_cast<std::uint8_t>((brs ? kCanFdBrs : 0) | (esi ? kCanFdEsi : 0));
    fr.len = static_cast<std::uint8_t>(length);
    if (!data(i + 4, fr)) return;
    const std::size_t flags_at = i + 4 + fr.len + 2;
    if (flags_at < f_.size()) {
      const auto flags = parse_log_number(f_[flags_at], 16, 0xFFFFFFFFu);
      if (!flags) return bad("CANFD: expected the message flags (hex) after duration and bit length");
      if (!(*flags & 0x1000)) {  // EDL clear: a classic frame logged in FD form
        if (fr.len > 8) return bad("CANFD: a classic frame (EDL clear) with more than 8 bytes");
        fr.fd = false, fr.fd_flags = 0;
        fr.rtr = (*flags & 0x10) != 0;
      }
    }
    log.frames.push_back(fr);
  }
};

}  // namespace

std::unique_ptr<LogSource> open_asc_log(std::istream& in) { return std::make_unique<TextLogSource<AscReader>>(in); }

ParsedLog read_asc_log(std::istream& in) { return read_whole_log(*open_asc_log(in)); }

ParsedLog parse_asc_log(std::string_view text) {
  std::istringstream in{std::string(text)};
  return read_asc_log(in);
}

bool sniff_asc_log(std::string_view head) {
  std::vector<std::string_view> f;
  bool found = false;
  int asked = 0;
  for_each_log_line(head, [&](std::string_view line) {
    split_log_fields(line, f);
    if (f.empty() || found || ++asked > 8) return;
    found = (equals_ignoring_case(f[0], "date") && f.size() >= 5) ||
            (equals_ignoring_case(f[0], "base") && f.size() >= 2 && (equals_ignoring_case(f[1], "hex") || equals_ignoring_case(f[1], "dec"))) ||
            (equals_ignoring_case(f[0], "begin") && f.size() >= 2 && equals_ignoring_case(f[1], "triggerblock"));
  });
  return found;
}

const LogFormat& asc_log_format() {
  static constexpr std::string_view kExtensions[] = {".asc"};
  static const LogFormat format{"asc", "date Sun Sep 12 03:15:14.717 am 2021", kExtensions, sniff_asc_log, open_asc_log,
                                write_asc_log};
  return format;
}

}  // namespace meter::controller
