// PCAN trace lines by file version: version 1 files have fixed columns after "<number>)", version
// 2 files name theirs in ";$COLUMNS=".
#include "meter/controller/input/trc_log.hpp"

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "meter/controller/input/candump_line.hpp"
#include "meter/controller/input/log_fields.hpp"
#include "meter/controller/input/log_lines.hpp"

namespace meter::controller {
namespace {

// The columns of each version, one letter each (PEAK's names): N number, O time offset (ms), T type,
// B bus, I id, d direction, R reserved, L DLC, l data length, D data bytes.
std::string_view trc_default_columns(int version) {
  switch (version) {
    case 10: return "NOILD";
    case 11: return "NOTILD";
    case 12: return "NOBTILD";
    case 13: return "NOBTIRLD";
    case 20: return "NOTIdlD";
    default: return "NOTBIdRLD";
  }
}

class TrcReader {
 public:
  explicit TrcReader(ParsedLog& window) : log(window) { set_columns(trc_default_columns(10)); }
  void line(std::string_view t) {
    ++log.lines;
    if (t.empty()) return;
    if (t[0] == ';') return header(t);
    split_log_fields(t, f_);
    message();
  }
  ParsedLog& log;

 private:
  std::vector<std::string_view> f_;
  int version_ = 10;
  std::string columns_;
  std::array<int, 128> at_{};  // each column letter's field index (its first), -1: not a column of this file
  bool has_dlc_ = true;                // an L column (else l, the data length)

  void set_columns(std::string_view columns) {
    columns_ = columns;
    at_.fill(-1);
    for (std::size_t i = columns_.size(); i-- > 0;)  // from the end: a letter given twice is its first
      if (static_cast<unsigned char>(columns_[i]) < 128) at_[static_cast<unsigned char>(columns_[i])] = static_cast<int>(i);
    has_dlc_ = at_['L'] >= 0;
  }

  void bad(std::string why) { log.bad_lines.push_back({log.lines, std::move(why)}); }

  void header(std::string_view t) {
    constexpr std::string_view kVersion = ";$FILEVERSION=", kColumns = ";$COLUMNS=";
    if (t.substr(0, kVersion.size()) == kVersion) {
      static constexpr std::pair<std::string_view, int> kVersions[] = {{"1.0", 10}, {"1.1", 11}, {"1.2", 12}, {"1.3", 13}, {"2.0", 20}, {"2.1", 21}};
      const std::string_view v = t.substr(kVersion.size());
      const auto* it = std::find_if(std::begin(kVersions), std::end(kVersions), [&](const auto& k) { return k.first == v; });
      if (it == std::end(kVersions)) return bad("file version: expected 1.0, 1.1, 1.2, 1.3, 2.0 or 2.1, got '" + std::string(v.substr(0, 12)) + "'");
      version_ = it->second;
      set_columns(trc_default_columns(version_));
    } else if (t.substr(0, kColumns.size()) == kColumns) {
      std::string cols;
      for (char c : t.substr(kColumns.size()))
        if (c != ',') cols += c;
      const auto has = [&](char c) { return cols.find(c) != std::string::npos; };
      if (cols.empty() || cols.find('D') != cols.size() - 1 || !has('O') || !has('I') || (!has('L') && !has('l')))
        return bad("columns: expected letters such as N,O,T,B,I,d,R,L,D with O, I and L (or l), and D last");
      set_columns(cols);
    }  // any other ';' line is a comment
  }

  std::optional<std::string_view> field(char column) const {
    const int i = at_[static_cast<unsigned char>(column) & 127];
    if (i < 0 || static_cast<std::size_t>(i) >= f_.size()) return std::nullopt;
    return f_[static_cast<std::size_t>(i)];
  }

  void message() {
    const std::size_t fixed = columns_.size() - 1;  // every column but the data bytes
    if (f_.size() < fixed)
      return bad("expected at least " + std::to_string(fixed) + " columns (" + columns_ + ", file version " +
                 std::to_string(version_ / 10) + "." + std::to_string(version_ % 10) + "), got " + std::to_string(f_.size()));
    const auto number = field('N');
    if (version_ < 20 && number && number->back() != ')') return bad("message number: expected '<n>)' in a version 1 file");
    const auto offset = parse_log_time(*field('O'), 1000000LL);
    if (!offset) return bad("time offset: expected milliseconds '<ms>[.<fraction>]'");
    CanFrame fr;
    fr.timestamp_ns = *offset;
    fr.channel = 1;
    if (const auto bus = field('B')) {
      const auto b = parse_log_number(*bus, 10, 255);
      if (!b || *b == 0) return bad("bus: expected a number 1..255");
      fr.channel = static_cast<std::uint8_t>(*b);
    }
    const std::string_view type = field('T').value_or("DT");
    if (!kind(type, fr)) return;
    if (fr.error) return log.frames.push_back(fr);
    const std::string_view id = *field('I');
    if (version_ == 10 && id == "FFFFFFFF") return void(++log.skipped);  // a bus status line
    fr.extended = id.size() > 4;
    const auto v = parse_log_number(id, 16, fr.extended ? 0x1FFFFFFFu : 0x7FFu);
    if (!v) return bad("id: expected hex, up to 7FF in 4 digits or 1FFFFFFF in more");
    fr.id = *v;
    length(fixed, fr);
  }

  // The type column: data, remote, CAN FD with its bits, error; false (and counted or reported)
  // for the rest.
  bool kind(std::string_view type, CanFrame& fr) {
    if (type.size() == 2 && ((type[0] == 'D' && type[1] == 'T') || (type[1] == 'x' && (type[0] == 'R' || type[0] == 'T')))) return true;
    if (type == "RR") return fr.rtr = true;
    if (type == "FD" || type == "FB" || type == "FE" || type == "BI") {
      fr.fd = true;
      fr.fd_flags = static_cast<std::uint8_t>((type == "FB" || type == "BI" ? kCanFdBrs : 0) | (type == "FE" || type == "BI" ? kCanFdEsi : 0));
      return true;
    }
    if (type == "ER" || type == "Error") return fr.error = true;
    if (type == "ST" || type == "EC" || type == "EV" || type == "Warng") return ++log.skipped, false;
    bad("type: expected Rx/Tx (version 1) or DT, RR, FD, FB, FE, BI, ER, ST, EC, EV, got '" + std::string(type.substr(0, 8)) + "'");
    return false;
  }

  void length(std::size_t fixed, CanFrame& fr) {
    const bool has_dlc = has_dlc_;
    const auto n = parse_log_number(*field(has_dlc ? 'L' : 'l'), 10, has_dlc ? 15 : 64);
    if (!n) return bad(has_dlc ? "DLC: expected 0..15" : "data length: expected 0..64");
    std::uint32_t len = has_dlc ? (fr.fd ? can_fd_dlc_to_len(static_cast<std::uint8_t>(*n)) : std::min<std::uint32_t>(*n, 8)) : *n;
    if (has_dlc && !fr.fd && *n > 8) fr.len8_dlc = static_cast<std::uint8_t>(*n);
    if (!fr.fd && len > 8) return bad("data length: a classic frame holds at most 8 bytes");
    if (fr.fd && !is_valid_fd_len(len)) return bad("data length: " + std::to_string(len) + " is not a CAN FD length");
    fr.len = static_cast<std::uint8_t>(len);
    const bool rtr_word = f_.size() == fixed + 1 && f_[fixed] == "RTR";  // version 1's remote frames
    if (fr.rtr || rtr_word) {
      fr.rtr = true;
      if (f_.size() != fixed + (rtr_word ? 1 : 0)) return bad("remote frame: expected no data bytes");
      return log.frames.push_back(fr);
    }
    if (f_.size() != fixed + len)
      return bad("expected " + std::to_string(fixed + len) + " columns (" + columns_ + " with " + std::to_string(len) +
                 " data bytes), got " + std::to_string(f_.size()));
    for (std::size_t i = 0; i < len; ++i) {
      const std::string_view b = f_[fixed + i];
      const unsigned hi = b.size() == 2 ? kLogDigitValue[static_cast<unsigned char>(b[0])] : 16;
      const unsigned lo = b.size() == 2 ? kLogDigitValue[static_cast<unsigned char>(b[1])] : 16;
      if ((hi | lo) >= 16) return bad("data byte " + std::to_string(i) + ": expected two hex digits");
      fr.data[i] = static_cast<std::uint8_t>(hi << 4 | lo);
    }
    log.frames.push_back(fr);
  }
};

}  // namespace

std::unique_ptr<LogSource> open_trc_log(std::istream& in) { return std::make_unique<TextLogSource<TrcReader>>(in); }

ParsedLog read_trc_log(std::istream& in) { return read_whole_log(*open_trc_log(in)); }

bool sniff_trc_log(std::string_view head) {
  if (head.find(";$FILEVERSION=") != std::string_view::npos) return true;
  // A version 1.0 / 1.1 file: a message line "<n>) <ms> ..." among the first non-comment lines.
  std::vector<std::string_view> f;
  bool found = false;
  int asked = 0;
  for_each_log_line(head, [&](std::string_view line) {
    if (found || line.empty() || line[0] == ';' || ++asked > 8) return;
    split_log_fields(line, f);
    found = f.size() >= 4 && f[0].size() > 1 && f[0].back() == ')' && parse_log_number(f[0].substr(0, f[0].size() - 1), 10, 0xFFFFFFFFu) &&
            parse_log_time(f[1], 1000000LL);
  });
  return found;
}

const LogFormat& trc_log_format() {
  static constexpr std::string_view kExtensions[] = {".trc"};
  static const LogFormat format{"trc", ";$FILEVERSION=1.1", kExtensions, sniff_trc_log, open_trc_log, nullptr};
  return format;
}

}  // namespace meter::controller
