#include "meter/controller/mapping/sources.hpp"

#include <algorithm>
#include <cmath>
#include <span>

#include "meter/controller/e2e/e2e_guard.hpp"

namespace meter::controller {

namespace {
// key names the source in errors; message.signal is what is looked up in db.
DbcSource resolve_in(const Database* db, const std::string& key, const std::string& message_signal, const std::string& file,
                     int line) {
  auto dot = message_signal.find('.');
  std::string msg = message_signal.substr(0, dot), sig = message_signal.substr(dot + 1);
  if (!db) throw MappingError(file, line, "source " + key + " needs a DBC (--dbc)");
  const DbcMessage* m = db->find(msg);
  if (!m) throw MappingError(file, line, "source " + key + ": the DBC " + db->file + " has no message '" + msg + "'" + db->skipped_note(msg));
  int si = m->find_signal(sig);
  if (si < 0) throw MappingError(file, line, "source " + key + ": message " + msg + " has no signal '" + sig + "'" + db->skipped_note(msg, sig));
  return DbcSource{m, si};
}
}  // namespace

DbcSource resolve_dbc_source(const Database* db, const std::string& key, const std::string& file, int line) {
  return resolve_in(db, key, key, file, line);
}

namespace {
std::string input_list(std::span<const InputDbc> inputs) {
  std::string list;
  for (const InputDbc& in : inputs) {
    if (in.name.empty()) continue;
    if (!list.empty()) list += ", ";
    list += in.name + (in.db ? " (" + in.db->file + ")" : " (no DBC)");
  }
  return list.empty() ? "one unnamed input" : list;
}
}  // namespace

InputSource resolve_input_source(std::span<const InputDbc> inputs, const std::string& key, const std::string& file,
                                 int line) {
  const auto first = key.find('.'), second = key.find('.', first + 1);
  if (second != std::string::npos) {
    // INPUT.Message.Signal
    const std::string name = key.substr(0, first);
    for (std::size_t i = 0; i < inputs.size(); ++i) {
      if (inputs[i].name != name) continue;
      if (!inputs[i].db)
        throw MappingError(file, line, "source " + key + ": input '" + name + "' has no DBC (give --dbc " + name + "=FILE)");
      return InputSource{static_cast<int>(i), resolve_in(inputs[i].db, key, key.substr(first + 1), file, line)};
    }
    throw MappingError(file, line, "source " + key + ": no input named '" + name + "'; expected INPUT.Message.Signal with INPUT one of: " +
                                       input_list(inputs));
  }
  // Message.Signal: the input whose DBC defines the message.
  std::vector<int> with_db, with_message;
  const std::string msg = key.substr(0, first);
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    if (!inputs[i].db) continue;
    with_db.push_back(static_cast<int>(i));
    if (inputs[i].db->find(msg)) with_message.push_back(static_cast<int>(i));
  }
  if (with_db.size() <= 1) {
    const int only = with_db.empty() ? 0 : with_db.front();
    const Database* db = with_db.empty() ? nullptr : inputs[static_cast<std::size_t>(only)].db;
    return InputSource{only, resolve_dbc_source(db, key, file, line)};
  }
  if (with_message.size() > 1) {
    std::string names;
    for (int i : with_message) names += (names.empty() ? "" : " and ") + inputs[static_cast<std::size_t>(i)].name;
    throw MappingError(file, line, "source " + key + " is ambiguous: the DBCs of inputs " + names + " define message '" +
                                       msg + "'; name the input, e.g. " + inputs[static_cast<std::size_t>(with_message.front())].name +
                                       "." + key);
  }
  if (with_message.empty()) {
    std::string hint;
    for (const InputDbc& in : inputs)
      if (in.name == msg) hint = " ('" + msg + "' is an input: expected " + msg + ".Message.Signal)";
    throw MappingError(file, line, "source " + key + ": no input's DBC has a message '" + msg + "' (inputs: " +
                                       input_list(inputs) + ")" + hint);
  }
  const int i = with_message.front();
  return InputSource{i, resolve_dbc_source(inputs[static_cast<std::size_t>(i)].db, key, file, line)};
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
      const InputSource r = resolve_input_source(inputs_, key, mapping_.file, o.line);
      s.input = r.input;
      s.dbc = r.dbc;
      const DbcSignal& ds = s.dbc.dbc_signal();
      s.reading.range_min = ds.minimum;
      s.reading.range_max = ds.maximum;
      s.cycle_ms = s.dbc.message->cycle_time_ms;
    } else if (const ModbusConfig* table = mapping_.modbus_table_of(key)) {
      s.cycle_ms = static_cast<int>(table->poll_s * 1000);
    }
    const int idx = static_cast<int>(sources_.size());
    sources_.push_back(std::move(s));
    by_key_.emplace(key, idx);
    if (const DbcSource& d = sources_.back().dbc; d.message) {
      MessageUse& use = by_message_[d.message];
      use.input = sources_.back().input;
      use.sources.resize(d.message->signals.size(), -1);
      use.sources[static_cast<std::size_t>(d.signal)] = idx;
    }
    indices.push_back(idx);
  }
  return indices;
}

FrameUse SourceTable::on_frame(const CanFrame& f) {
  if (f.error) return FrameUse::ErrorFrame;
  const Database* db = f.input < inputs_.size() ? inputs_[f.input].db : nullptr;
  if (f.rtr || !db) return FrameUse::Ignored;
  const DbcMessage* m = db->find(f.id, f.extended);
  if (!m) return FrameUse::UnknownId;
  const std::span<const std::uint8_t> payload(f.data.data(), f.len);
  if (e2e_ && !e2e_->accept(m, f.id, payload)) return FrameUse::Refused;
  auto it = by_message_.find(m);
  if (it == by_message_.end()) return FrameUse::Unused;
  decode(*m, payload, scratch_);
  for (const auto& d : scratch_) {
    int si = it->second.sources[static_cast<std::size_t>(d.signal)];
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

std::vector<std::pair<std::uint32_t, bool>> SourceTable::used_ids(int input) const {
  std::vector<std::pair<std::uint32_t, bool>> ids;
  for (const auto& [m, use] : by_message_)
    if (use.input == input) ids.emplace_back(m->id, m->extended);
  std::sort(ids.begin(), ids.end());
  return ids;
}

}  // namespace meter::controller
