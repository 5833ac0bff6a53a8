#include "meter/controller/e2e/e2e_message.hpp"

#include <stdexcept>
#include <vector>

#include "meter/controller/dbc/codec.hpp"
#include "meter/controller/e2e/autosar_profile05.hpp"
#include "meter/controller/e2e/autosar_profile11.hpp"
#include "meter/controller/e2e/chrysler_checksum.hpp"
#include "meter/controller/e2e/honda_checksum.hpp"
#include "meter/controller/e2e/hyundai_canfd_checksum.hpp"
#include "meter/controller/e2e/hyundai_checksum.hpp"
#include "meter/controller/e2e/mazda_checksum.hpp"
#include "meter/controller/e2e/nissan_checksum.hpp"
#include "meter/controller/e2e/subaru_checksum.hpp"
#include "meter/controller/e2e/subaru_preglobal_checksum.hpp"
#include "meter/controller/e2e/tesla_checksum.hpp"
#include "meter/controller/e2e/toyota_checksum.hpp"
#include "meter/controller/e2e/vw_mqb_checksum.hpp"

namespace meter::controller {
namespace {

bool named_like(std::string_view name, std::initializer_list<std::string_view> words) {
  for (std::string_view w : words) {
    if (name.size() != w.size()) continue;
    bool same = true;
    for (std::size_t i = 0; i < w.size() && same; ++i)
      same = (name[i] >= 'a' && name[i] <= 'z' ? static_cast<char>(name[i] - 32) : name[i]) == w[i];
    if (same) return true;
  }
  return false;
}

int first_named_like(const DbcMessage& m, std::initializer_list<std::string_view> words) {
  for (std::size_t i = 0; i < m.signals.size(); ++i)
    if (named_like(m.signals[i].name, words)) return static_cast<int>(i);
  return -1;
}

int find_role(const DbcMessage& m, const std::string& named, int conventional, const char* role) {
  if (named.empty()) return conventional;
  const int i = m.find_signal(named);
  if (i < 0) throw std::invalid_argument("message " + m.name + " has no " + role + " signal '" + named + "'");
  return i;
}

// The bytes the signal's bits cover, one mask byte per payload byte.
std::vector<std::uint8_t> bit_mask(const DbcSignal& s, std::size_t size) {
  std::vector<std::uint8_t> mask(std::max<std::size_t>(size, s.bytes_needed()), 0);
  const std::uint64_t ones = s.length >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << s.length) - 1;
  insert_raw(s, ones, mask);
  return mask;
}

// Where the checksum must sit for each algorithm: which bytes (any, first, last) and how wide.
struct Place {
  enum Where { AnyByte, FirstByte, LastByte, LowNibbleOfLast, AnyNibble, FirstTwoBytes, AnyTwoBytes } where;
};
Place place_of(ChecksumKind k) {
  switch (k) {
    case ChecksumKind::Toyota:
    case ChecksumKind::Chrysler:
    case ChecksumKind::Nissan:
    case ChecksumKind::Mazda: return {Place::LastByte};
    case ChecksumKind::Honda: return {Place::LowNibbleOfLast};
    case ChecksumKind::VwMqb:
    case ChecksumKind::Profile02:
    case ChecksumKind::Subaru: return {Place::FirstByte};
    case ChecksumKind::Hyundai: return {Place::AnyNibble};
    case ChecksumKind::HyundaiCanFd: return {Place::FirstTwoBytes};
    case ChecksumKind::Profile05: return {Place::AnyTwoBytes};
    default: return {Place::AnyByte};
  }
}

std::string place_text(Place p) {
  // In the order of Place::Where.
  static const char* const kText[] = {"one whole byte", "byte 0", "the last byte", "the low nibble of the last byte",
                                      "one nibble", "bytes 0-1, little-endian", "two whole bytes, little-endian"};
  return kText[p.where];
}

// Sets e.checksum_byte/bit when the signal sits where the algorithm writes its checksum.
bool locate_checksum(E2eMessage& e, const DbcSignal& s) {
  const auto mask = bit_mask(s, e.message->size);
  std::vector<std::size_t> used;
  for (std::size_t i = 0; i < mask.size(); ++i)
    if (mask[i]) used.push_back(i);
  if (used.empty()) return false;
  const std::size_t first = used.front(), last_byte = mask.size() - 1;
  e.checksum_byte = first;
  e.checksum_bit = static_cast<unsigned>(first * 8);
  const Place p = place_of(e.spec.checksum);
  const bool one_byte = used.size() == 1 && mask[first] == 0xFF;
  const bool nibble = used.size() == 1 && (mask[first] == 0x0F || mask[first] == 0xF0);
  if (nibble && mask[first] == 0xF0) e.checksum_bit += 4;
  const bool two_le = used.size() == 2 && used[1] == first + 1 && mask[first] == 0xFF && mask[first + 1] == 0xFF && s.little_endian;
  switch (p.where) {
    case Place::AnyByte: return one_byte;
    case Place::FirstByte: return one_byte && first == 0;
    case Place::LastByte: return one_byte && first == last_byte;
    case Place::LowNibbleOfLast: return nibble && first == last_byte && mask[first] == 0x0F;
    case Place::AnyNibble: return nibble;
    case Place::FirstTwoBytes: return two_le && first == 0;
    case Place::AnyTwoBytes: return two_le;
  }
  return false;
}

void set_data_ids(E2eMessage& e) {
  const auto& list = e.spec.data_ids;
  if (!list.empty()) {
    if (list.size() != 16) throw std::invalid_argument("message " + e.message->name + ": data_ids: expected 16 values, got " + std::to_string(list.size()));
    std::copy(list.begin(), list.end(), e.data_ids.begin());
  } else if (e.spec.checksum == ChecksumKind::VwMqb) {
    const auto known = vw_mqb_data_ids(e.message->id);
    if (!known) throw std::invalid_argument("message " + e.message->name + ": no built-in VW MQB data id list for its id; give data_ids");
    e.data_ids = *known;
  } else if (e.spec.checksum == ChecksumKind::Profile02) {
    throw std::invalid_argument("message " + e.message->name + ": autosar-p02 needs data_ids (16 values)");
  }
}

}  // namespace

int checksum_signal_of(const DbcMessage& m) { return first_named_like(m, {"CHECKSUM", "CRC", "CHKSUM"}); }
int counter_signal_of(const DbcMessage& m) {
  return first_named_like(m, {"COUNTER", "CTR", "ALIVE_COUNTER", "ROLLING_COUNTER"});
}

std::string_view to_string(ChecksumStatus s) {
  switch (s) {
    case ChecksumStatus::Ok: return "ok";
    case ChecksumStatus::Bad: return "bad";
    case ChecksumStatus::NotChecked: return "none";
    case ChecksumStatus::ShortFrame: return "short-frame";
  }
  return "unknown";
}

E2eMessage resolve_e2e(const E2eSpec& spec, const DbcMessage& m, int input) {
  E2eMessage e;
  e.message = &m;
  e.input = input;
  e.spec = spec;
  if (spec.checksum != ChecksumKind::None) {
    e.checksum_signal = find_role(m, spec.checksum_signal, checksum_signal_of(m), "checksum");
    if (e.checksum_signal < 0)
      throw std::invalid_argument("message " + m.name + " has no signal named CHECKSUM, CRC or CHKSUM; name it with checksum_signal");
    const DbcSignal& s = m.signals[static_cast<std::size_t>(e.checksum_signal)];
    if (!locate_checksum(e, s))
      throw std::invalid_argument("message " + m.name + ": " + std::string(to_string(spec.checksum)) + " writes its checksum in " +
                                  place_text(place_of(spec.checksum)) + ", but signal " + s.name + " is " +
                                  std::to_string(s.length) + " bits at start bit " + std::to_string(s.start_bit));
    set_data_ids(e);
  }
  if (spec.counter) {
    e.counter_signal = find_role(m, spec.counter_signal, counter_signal_of(m), "counter");
    if (e.counter_signal >= 0) {
      const DbcSignal& c = m.signals[static_cast<std::size_t>(e.counter_signal)];
      if (c.length > 16) throw std::invalid_argument("message " + m.name + ": counter " + c.name + " is " + std::to_string(c.length) + " bits; expected 1..16");
      const bool p01 = spec.checksum == ChecksumKind::Profile01;  // 0..14: 15 is never sent
      e.counter_modulus = p01 ? 15 : (1u << c.length);
    }
  }
  if (e.checksum_signal < 0 && e.counter_signal < 0)
    throw std::invalid_argument("message " + m.name + ": neither a checksum nor a counter to check");
  return e;
}

std::optional<std::uint32_t> expected_checksum(const E2eMessage& m, std::uint32_t id, std::span<const std::uint8_t> p,
                                               std::uint32_t counter) {
  const E2eSpec& s = m.spec;
  switch (s.checksum) {
    case ChecksumKind::None: return std::nullopt;
    case ChecksumKind::Toyota: return toyota_checksum(id, p);
    case ChecksumKind::Honda: return honda_checksum(id, m.message->extended, p);
    case ChecksumKind::VwMqb:
    case ChecksumKind::Profile02: return p.size() < 2 ? std::nullopt : std::optional<std::uint32_t>(autosar_profile02_crc(p, m.data_ids, p[1] & 0x0F));
    case ChecksumKind::Hyundai: return hyundai_checksum(p, m.checksum_bit);
    case ChecksumKind::HyundaiCanFd: {
      auto v = hyundai_canfd_checksum(id, p);
      return v ? std::optional<std::uint32_t>(*v) : std::nullopt;
    }
    case ChecksumKind::Subaru: return subaru_checksum(id, p);
    case ChecksumKind::SubaruPreglobal: return subaru_preglobal_checksum(p, m.checksum_byte);
    case ChecksumKind::Chrysler: return chrysler_checksum(p);
    case ChecksumKind::Nissan: return nissan_checksum(p);
    case ChecksumKind::Mazda: return mazda_checksum(p);
    case ChecksumKind::Tesla: return tesla_checksum(id, p, m.checksum_byte);
    case ChecksumKind::Profile01: return autosar_profile01_crc(p, m.checksum_byte, s.data_id, s.data_id_mode, counter);
    case ChecksumKind::Profile11: return autosar_profile11_crc(p, m.checksum_byte, s.data_id, s.data_id_mode);
    case ChecksumKind::Profile05: return autosar_profile05_crc(p, m.checksum_byte, s.data_id);
  }
  return std::nullopt;
}

FrameCheck check_frame(const E2eMessage& m, CounterState& state, std::uint32_t id, std::span<const std::uint8_t> p) {
  FrameCheck r;
  const DbcSignal* counter = m.counter_signal >= 0 ? &m.message->signals[static_cast<std::size_t>(m.counter_signal)] : nullptr;
  const DbcSignal* sum = m.checksum_signal >= 0 ? &m.message->signals[static_cast<std::size_t>(m.checksum_signal)] : nullptr;
  if ((counter && counter->bytes_needed() > p.size()) || (sum && sum->bytes_needed() > p.size())) {
    r.checksum = ChecksumStatus::ShortFrame;
    return r;
  }
  if (counter) {
    r.has_counter = true;
    r.counter = static_cast<std::uint32_t>(extract_raw(*counter, p));
  }
  if (sum) {
    r.received = static_cast<std::uint32_t>(extract_raw(*sum, p));
    const auto want = expected_checksum(m, id, p, r.counter);
    bool ok = want && *want == r.received;
    if (ok && m.spec.checksum == ChecksumKind::Profile11) ok = autosar_profile11_nibble_ok(p, m.spec.data_id, m.spec.data_id_mode);
    r.expected = want.value_or(0);
    r.checksum = ok ? ChecksumStatus::Ok : ChecksumStatus::Bad;
    if (!ok) return r;
  }
  if (counter && m.spec.checksum == ChecksumKind::Profile01 && r.counter > 14) {
    r.counter_result.status = CounterStatus::WrongSequence;  // profile 1 counts 0..14: 15 is never sent
  } else if (counter) {
    r.counter_result = check_counter(state, r.counter, m.counter_modulus, m.spec.tolerance);
    r.usable = counter_usable(r.counter_result.status);
  } else {
    r.usable = true;
  }
  return r;
}

}  // namespace meter::controller
