#include "meter/controller/e2e/e2e_guard.hpp"

#include <algorithm>
#include <functional>
#include <stdexcept>

#include "meter/controller/e2e/e2e_detect.hpp"
#include "meter/controller/mapping/mapping.hpp"
#include "meter/controller/mapping/sources.hpp"

namespace meter::controller {

namespace {
// The sorted table's first entry not before message m.
template <class Table>
auto lower_bound_of(Table& table, const DbcMessage* m) {
  return std::lower_bound(table.begin(), table.end(), m, [](const auto& e, const DbcMessage* key) { return std::less<>()(e.first, key); });
}
}  // namespace

void E2eGuard::add(E2eMessage message) {
  const DbcMessage* m = message.message;
  const auto at = lower_bound_of(by_message_, m);
  if (at != by_message_.end() && at->first == m) return;  // configured before (the map file wins over detection)
  by_message_.insert(at, {m, entries_.size()});
  entries_.push_back(Entry{std::move(message), {}, {}});
}

int E2eGuard::find(const DbcMessage* m) const {
  const auto at = lower_bound_of(by_message_, m);
  return at == by_message_.end() || at->first != m ? -1 : static_cast<int>(at->second);
}

FrameCheck E2eGuard::check(std::size_t i, std::uint32_t id, std::span<const std::uint8_t> payload) {
  Entry& e = entries_[i];
  const FrameCheck r = check_frame(e.message, e.state, id, payload);
  E2eMessageStats& s = e.stats;
  ++s.checked;
  if (r.usable) ++s.used;
  if (r.checksum == ChecksumStatus::Bad) ++s.checksum_failed;
  if (r.checksum == ChecksumStatus::ShortFrame) ++s.short_frames;
  if (r.checksum == ChecksumStatus::Bad || r.checksum == ChecksumStatus::ShortFrame || !r.has_counter) return r;
  switch (r.counter_result.status) {
    case CounterStatus::Repeated: ++s.repeated; break;
    case CounterStatus::WrongSequence: ++s.wrong_sequence; break;
    case CounterStatus::Syncing: ++s.syncing; break;
    case CounterStatus::Skipped:
      ++s.skips;
      s.lost += r.counter_result.lost;
      break;
    case CounterStatus::Initial:
    case CounterStatus::Ok: break;
  }
  return r;
}

bool E2eGuard::likely_mismatch(const Entry& e) const {
  const E2eMessageStats& s = e.stats;
  return s.checked >= min_frames_ && s.checked > 0 &&
         static_cast<double>(s.refused()) >= ratio_ * static_cast<double>(s.checked);
}

namespace {

// "INPUT.Message" or "Message" -> (input, message).
std::pair<int, const DbcMessage*> find_message(std::span<const InputDbc> inputs, const E2eSpec& spec, const std::string& file) {
  const auto dot = spec.message.find('.');
  if (dot != std::string::npos) {
    const std::string input = spec.message.substr(0, dot), name = spec.message.substr(dot + 1);
    for (std::size_t i = 0; i < inputs.size(); ++i) {
      if (inputs[i].name != input) continue;
      if (!inputs[i].db) throw MappingError(file, spec.line, "[e2e " + spec.message + "]: input '" + input + "' has no DBC");
      if (const DbcMessage* m = inputs[i].db->find(name)) return {static_cast<int>(i), m};
      throw MappingError(file, spec.line, "[e2e " + spec.message + "]: the DBC " + inputs[i].db->file + " has no message '" + name + "'");
    }
    throw MappingError(file, spec.line, "[e2e " + spec.message + "]: no input named '" + input + "'");
  }
  std::pair<int, const DbcMessage*> found{-1, nullptr};
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const DbcMessage* m = inputs[i].db ? inputs[i].db->find(spec.message) : nullptr;
    if (!m) continue;
    if (found.second)
      throw MappingError(file, spec.line, "[e2e " + spec.message + "] is ambiguous: several inputs' DBCs define it; name the input ([e2e INPUT." + spec.message + "])");
    found = {static_cast<int>(i), m};
  }
  if (!found.second) throw MappingError(file, spec.line, "[e2e " + spec.message + "]: no input's DBC has a message '" + spec.message + "'");
  return found;
}

}  // namespace

E2eGuard build_e2e_guard(std::span<const InputDbc> inputs, const E2eSettings& settings, const std::string& file) {
  E2eGuard guard(settings);
  for (const E2eSpec& spec : settings.messages) {
    const auto [input, m] = find_message(inputs, spec, file);
    try {
      guard.add(resolve_e2e(spec, *m, input));
    } catch (const std::invalid_argument& e) {
      throw MappingError(file, spec.line, "[e2e " + spec.message + "]: " + e.what());
    }
  }
  if (!settings.detect) return guard;
  for (std::size_t i = 0; i < inputs.size(); ++i)
    if (inputs[i].db) add_detected_e2e(guard, *inputs[i].db, static_cast<int>(i), detect_e2e(*inputs[i].db));
  return guard;
}

void add_detected_e2e(E2eGuard& guard, const Database& db, int input, const E2eDetection& detection) {
  for (const E2eSpec& spec : detection.messages)
    if (const DbcMessage* m = db.find(spec.message)) guard.add(resolve_e2e(spec, *m, input));
}

void update_e2e_health(const E2eGuard& guard, std::vector<E2eHealth>& health) {
  const auto& entries = guard.entries();
  health.resize(entries.size());
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const E2eMessageStats& s = entries[i].stats;
    E2eHealth& h = health[i];
    if (h.message != entries[i].message.message->name) h.message = entries[i].message.message->name;
    h.checked = s.checked;
    h.refused = s.refused();
    h.checksum = s.checksum_failed + s.short_frames;
    h.repeated = s.repeated;
    h.out_of_sequence = s.wrong_sequence + s.syncing;
    h.lost = s.lost;
    h.mismatch = guard.likely_mismatch(entries[i]);
  }
}

}  // namespace meter::controller
