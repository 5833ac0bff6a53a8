#include "meter/controller/mapping/e2e_section.hpp"

#include <algorithm>
#include <cerrno>
#include <iterator>
#include <cmath>
#include <cstdlib>

#include "meter/controller/mapping/mapping.hpp"

namespace meter::controller {
namespace {

struct E2eWhere {
  const std::string& file;
  int line;
  [[noreturn]] void fail(const std::string& what) const { throw MappingError(file, line, what); }
  // A whole number in [lo, hi], decimal or 0x hexadecimal.
  unsigned long whole(std::string_view text, const std::string& key, unsigned long lo, unsigned long hi) const {
    const std::string t(text);
    char* end = nullptr;
    errno = 0;
    const unsigned long v = std::strtoul(t.c_str(), &end, 0);
    if (t.empty() || t[0] == '-' || t[0] == '+' || end != t.c_str() + t.size() || errno == ERANGE || v < lo || v > hi)
      fail(key + ": expected a whole number " + std::to_string(lo) + ".." + std::to_string(hi) + " (decimal or 0x hex), got '" + t + "'");
    return v;
  }
};

// The values of a data id list: whole numbers separated by blanks or commas.
std::vector<std::uint8_t> data_id_list(std::string_view value, const E2eWhere& w) {
  std::vector<std::uint8_t> out;
  std::size_t i = 0;
  while (i < value.size()) {
    const std::size_t end = value.find_first_of(" \t,", i);
    const std::string_view item = value.substr(i, end == std::string_view::npos ? std::string_view::npos : end - i);
    if (!item.empty()) out.push_back(static_cast<std::uint8_t>(w.whole(item, "data_ids", 0, 255)));
    if (end == std::string_view::npos) break;
    i = end + 1;
  }
  if (out.size() != 16) w.fail("data_ids: expected 16 values (one per counter value 0..15), got " + std::to_string(out.size()));
  return out;
}

bool is_profile(ChecksumKind k) {
  return k == ChecksumKind::Profile01 || k == ChecksumKind::Profile05 || k == ChecksumKind::Profile11;
}

}  // namespace

void set_e2e_key(E2eSettings& s, const std::string& key, std::string_view value, const std::string& file, int line) {
  const E2eWhere w{file, line};
  if (key == "detect") {
    if (value == "true" || value == "yes") s.detect = true;
    else if (value == "false" || value == "no") s.detect = false;
    else w.fail("detect: expected true or false, got '" + std::string(value) + "'");
  } else if (key == "mismatch_ratio") {
    const std::string t(value);
    char* end = nullptr;
    const double r = std::strtod(t.c_str(), &end);
    if (end != t.c_str() + t.size() || !std::isfinite(r) || r <= 0 || r > 1)
      w.fail("mismatch_ratio: expected the refused share that marks a mismatch, in (0, 1], got '" + t + "'");
    s.mismatch_ratio = r;
  } else if (key == "mismatch_frames") {
    s.mismatch_min_frames = static_cast<unsigned>(w.whole(value, key, 1, 1000000));
  } else {
    w.fail("unknown [e2e] key '" + key + "'; expected detect, mismatch_ratio or mismatch_frames");
  }
}

void set_e2e_message_key(E2eSpec& s, const std::string& key, std::string_view value, const std::string& file, int line) {
  const E2eWhere w{file, line};
  const std::string v(value);
  if (key == "checksum") {
    const auto k = checksum_kind_named(v);
    if (!k) w.fail("checksum: expected one of " + checksum_kind_names() + ", got '" + v + "'");
    s.checksum = *k;
  } else if (key == "checksum_signal") {
    s.checksum_signal = v;
  } else if (key == "counter_signal") {
    s.counter = v != "none";
    s.counter_signal = s.counter ? v : "";
  } else if (key == "data_id") {
    s.data_id = static_cast<std::uint16_t>(w.whole(value, key, 0, 0xFFFF));
  } else if (key == "data_id_mode") {
    // In the order of DataIdMode.
    static const char* const kModes[] = {"both", "alternating", "low", "nibble"};
    const auto* it = std::find(std::begin(kModes), std::end(kModes), v);
    if (it == std::end(kModes)) w.fail("data_id_mode: expected both, alternating, low or nibble, got '" + v + "'");
    s.data_id_mode = static_cast<DataIdMode>(it - std::begin(kModes));
  } else if (key == "data_ids") {
    s.data_ids = data_id_list(value, w);
  } else if (key == "max_delta") {
    s.tolerance.max_delta = static_cast<unsigned>(w.whole(value, key, 1, 255));
  } else if (key == "sync_frames") {
    s.tolerance.sync_frames = static_cast<unsigned>(w.whole(value, key, 0, 255));
  } else if (key == "max_repeated") {
    s.tolerance.max_repeated = static_cast<unsigned>(w.whole(value, key, 0, 255));
  } else {
    w.fail("unknown [e2e " + s.message + "] key '" + key +
           "'; expected checksum, checksum_signal, counter_signal, data_id, data_id_mode, data_ids, max_delta, sync_frames, max_repeated");
  }
}

void check_e2e_message(const E2eSpec& s, const std::string& file) {
  const E2eWhere w{file, s.line};
  const std::string name = std::string(to_string(s.checksum));
  if (s.checksum == ChecksumKind::Profile02 && s.data_ids.empty()) w.fail("[e2e " + s.message + "]: autosar-p02 needs data_ids (16 values)");
  if (!s.data_ids.empty() && s.checksum != ChecksumKind::Profile02 && s.checksum != ChecksumKind::VwMqb)
    w.fail("[e2e " + s.message + "]: data_ids belongs to autosar-p02 and vw-mqb, not " + name);
  if (s.data_id != 0 && !is_profile(s.checksum))
    w.fail("[e2e " + s.message + "]: data_id belongs to autosar-p01, autosar-p05 and autosar-p11, not " + name);
  if (s.data_id_mode != DataIdMode::Both && s.checksum != ChecksumKind::Profile01 && s.checksum != ChecksumKind::Profile11)
    w.fail("[e2e " + s.message + "]: data_id_mode belongs to autosar-p01 and autosar-p11, not " + name);
  if (s.checksum == ChecksumKind::Profile11 && (s.data_id_mode == DataIdMode::Alternating || s.data_id_mode == DataIdMode::Low))
    w.fail("[e2e " + s.message + "]: autosar-p11 has data_id_mode both or nibble only");
  if (s.checksum == ChecksumKind::None && !s.counter) w.fail("[e2e " + s.message + "]: neither a checksum nor a counter to check");
}

}  // namespace meter::controller
