#include "meter/controller/mapping/sources.hpp"

#include <algorithm>
#include <cmath>
#include <span>

namespace meter::controller {

DbcSource resolve_dbc_source(const Database* db, const std::string& key, const std::string& file, int line) {
  auto dot = key.find('.');
  std::string msg = key.substr(0, dot), sig = key.substr(dot + 1);
  if (!db) throw MappingError(file, line, "source " + key + " needs a DBC (--dbc)");
  const DbcMessage* m = db->find(msg);
  if (!m) throw MappingError(file, line, "source " + key + ": the DBC " + db->file + " has no message '" + msg + "'" + db->skipped_note(msg));
  int si = m->find_signal(sig);
  if (si < 0) throw MappingError(file, line, "source " + key + ": message " + msg + " has no signal '" + sig + "'" + db->skipped_note(msg, sig));
  return DbcSource{m, si};
}

std::vector<int> SourceTable::add(const OutputMapping& o) {
  std::vector<int> indices;
  for (const std::string& key : o.sources) {
    auto it = by_key_.find(key);
    if (it != by_key_.end()) {
      indices.push_back(it->second);
      continue;
    }
    Source s;
    s.key = key;
    if (!is_modbus_source(key)) {
      s.dbc = resolve_dbc_source(db_, key, mapping_.file, o.line);
      const DbcSignal& ds = s.dbc.dbc_signal();
      s.reading.range_min = ds.minimum;
      s.reading.range_max = ds.maximum;
      s.cycle_ms = s.dbc.message->cycle_time_ms;
    } else if (mapping_.modbus) {
      s.cycle_ms = static_cast<int>(mapping_.modbus->poll_s * 1000);
    }
    const int idx = static_cast<int>(sources_.size());
    sources_.push_back(std::move(s));
    by_key_.emplace(key, idx);
    if (const DbcSource& d = sources_.back().dbc; d.message) {
      auto& table = by_message_[d.message];
      table.resize(d.message->signals.size(), -1);
      table[static_cast<std::size_t>(d.signal)] = idx;
    }
    indices.push_back(idx);
  }
  return indices;
}

FrameUse SourceTable::on_frame(const CanFrame& f) {
  if (f.error) return FrameUse::ErrorFrame;
  if (f.rtr || !db_) return FrameUse::Ignored;
  const DbcMessage* m = db_->find(f.id, f.extended);
  if (!m) return FrameUse::UnknownId;
  auto it = by_message_.find(m);
  if (it == by_message_.end()) return FrameUse::Unused;
  decode(*m, std::span<const std::uint8_t>(f.data.data(), f.len), scratch_);
  for (const auto& d : scratch_) {
    int si = it->second[static_cast<std::size_t>(d.signal)];
    if (si < 0) continue;
    Source& s = sources_[static_cast<std::size_t>(si)];
    s.reading.value = d.physical;
    s.reading.valid = d.status == DecodeStatus::Valid || d.status == DecodeStatus::OutOfRange;
    s.reading.out_of_range = d.status == DecodeStatus::OutOfRange;
    s.reading.received = true;
    s.reading.last_rx_ns = f.timestamp_ns;
    s.raw = d.raw;
    ++s.rx_count;
  }
  return FrameUse::Mapped;
}

bool SourceTable::on_value(std::string_view key, double value, bool valid, std::int64_t t) {
  auto it = by_key_.find(std::string(key));
  if (it == by_key_.end()) return false;
  Source& s = sources_[static_cast<std::size_t>(it->second)];
  s.reading.valid = valid && std::isfinite(value);
  s.reading.value = s.reading.valid ? value : 0.0;
  s.reading.out_of_range = false;
  s.reading.received = true;
  s.reading.last_rx_ns = t;
  ++s.rx_count;
  return true;
}

std::vector<std::pair<std::uint32_t, bool>> SourceTable::used_ids() const {
  std::vector<std::pair<std::uint32_t, bool>> ids;
  for (const auto& [m, signals] : by_message_) ids.emplace_back(m->id, m->extended);
  std::sort(ids.begin(), ids.end());
  return ids;
}

}  // namespace meter::controller
