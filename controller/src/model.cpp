#include "meter/controller/model.hpp"

#include <algorithm>
#include <cmath>

namespace meter::controller {

using protocol::SignalKind;
using protocol::SignalStatus;

struct Model::Slot {
  std::string key;
  const DbcMessage* message = nullptr;
  int signal = -1;
  double dbc_min = 0, dbc_max = 0;
  bool has_range = false;
  std::optional<int> cycle_ms;
  double value = 0;
  std::uint64_t raw = 0;
  DecodeStatus status = DecodeStatus::Valid;
  bool valid = false;
  bool received = false;
  std::int64_t last_rx = 0;
  std::uint64_t rx_count = 0;
};

struct Model::Out {
  std::size_t map = 0;   // index into mapping_.outputs
  std::size_t index = 0;  // index into outputs_
  SignalKind kind = SignalKind::Gauge;
  std::vector<int> slots;
  std::int64_t timeout_ns = -1, first_timeout_ns = -1;
  std::optional<NeedleFilter> needle;
  std::optional<FuelFilter> fuel;
  std::optional<SeatBeltReminder> belt;
  std::optional<Hysteresis> hyst;
  bool was_valid = false;
  double last_good = 0;
  bool has_good = false;
  double truth = 0;
  bool truth_valid = false;
  bool request = false;
  std::int64_t request_since = 0;
  std::uint64_t counter_seen = 0;
};

namespace {
bool is_telltale(SignalKind k) { return k == SignalKind::Telltale; }
}  // namespace

Model::Model(const Database* db, Mapping mapping, ModelOptions options)
    : db_(db), mapping_(std::move(mapping)), options_(std::move(options)), bulb_(mapping_.bulb_check_s) {
  resolve_sources();
  if (!options_.state_dir.empty() && mapping_.find(protocol::sig::kOdometer)) {
    store_ = std::make_unique<OdometerStore>(options_.state_dir);
    if (auto r = store_->load()) {
      odo_.set(r->odo_um, r->trip_um);
      persist_seq_ = r->sequence;
    }
  }
}

Model::~Model() = default;

void Model::resolve_sources() {
  auto slot_for = [&](const std::string& key, const OutputMapping& o) -> int {
    auto it = slot_by_key_.find(key);
    if (it != slot_by_key_.end()) return it->second;
    Slot s;
    s.key = key;
    if (key.rfind("modbus.", 0) != 0) {
      auto dot = key.find('.');
      std::string msg = key.substr(0, dot), sig = key.substr(dot + 1);
      if (!db_) throw MappingError(mapping_.file, o.line, "source " + key + " needs a DBC (--dbc)");
      const DbcMessage* m = db_->find(msg);
      if (!m) throw MappingError(mapping_.file, o.line, "source " + key + ": the DBC " + db_->file + " has no message '" + msg + "'");
      int si = m->find_signal(sig);
      if (si < 0) throw MappingError(mapping_.file, o.line, "source " + key + ": message " + msg + " has no signal '" + sig + "'");
      const DbcSignal& ds = m->signals[static_cast<std::size_t>(si)];
      s.message = m;
      s.signal = si;
      s.has_range = ds.has_range();
      s.dbc_min = ds.minimum;
      s.dbc_max = ds.maximum;
      s.cycle_ms = m->cycle_time_ms;
    }
    int idx = static_cast<int>(slots_.size());
    slots_.push_back(std::move(s));
    slot_by_key_.emplace(key, idx);
    if (slots_.back().message) {
      auto& table = slots_by_message_[slots_.back().message];
      table.resize(slots_.back().message->signals.size(), -1);
      table[static_cast<std::size_t>(slots_.back().signal)] = idx;
    }
    return idx;
  };
  // Speed first, rules last: fuel and seat belt read the speed, rules read displayed values.
  std::vector<std::size_t> order(mapping_.outputs.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  auto rank = [&](std::size_t i) {
    const auto& o = mapping_.outputs[i];
    if (o.id == protocol::sig::kSpeed) return 0;
    if (o.id == protocol::sig::kIgnition) return 1;
    if (o.rule == Rule::Below || o.rule == Rule::Above) return 3;
    if (o.accumulate != Accumulate::None) return 4;
    return 2;
  };
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return rank(a) < rank(b); });
  for (std::size_t i : order) {
    const OutputMapping& m = mapping_.outputs[i];
    Out o;
    o.map = i;
    o.kind = protocol::find_signal(m.id)->kind;
    o.index = outputs_.size();
    outputs_.push_back(ModelOutput{m.id});
    for (const auto& src : m.sources) o.slots.push_back(slot_for(src, m));
    // Timeouts: explicit, or AUTOSAR-COM style from the slowest source message's cycle time
    // (later timeout = 3 cycles; first timeout = 10 cycles, at least 1 s, for the bus to come up).
    if (m.timeout_s) {
      o.timeout_ns = static_cast<std::int64_t>(*m.timeout_s * 1e9);
    } else if (m.timeout_auto && !o.slots.empty() && m.accumulate == Accumulate::None) {
      int cycle = 0;
      for (int s : o.slots) {
        const Slot& sl = slots_[static_cast<std::size_t>(s)];
        if (sl.key.rfind("modbus.", 0) == 0 && mapping_.modbus) {
          cycle = std::max(cycle, static_cast<int>(mapping_.modbus->poll_s * 1000));
          continue;
        }
        if (!sl.cycle_ms)
          throw MappingError(mapping_.file, m.line, "[" + m.name + "] timeout = auto, but " + sl.key +
                                                        " has no GenMsgCycleTime in the DBC; give 'timeout = <seconds>' or 'none'");
        cycle = std::max(cycle, *sl.cycle_ms);
      }
      o.timeout_ns = static_cast<std::int64_t>(cycle) * 3 * 1000000;
      o.first_timeout_ns = std::max<std::int64_t>(1000000000, static_cast<std::int64_t>(cycle) * 10 * 1000000);
    }
    if (m.first_timeout_s) o.first_timeout_ns = static_cast<std::int64_t>(*m.first_timeout_s * 1e9);
    else if (o.first_timeout_ns < 0 && o.timeout_ns >= 0) o.first_timeout_ns = std::max<std::int64_t>(1000000000, o.timeout_ns);
    if (m.needle_tau_s > 0) o.needle.emplace(m.needle_tau_s);
    if (m.fuel) o.fuel.emplace(m.fuel_config);
    if (m.rule == Rule::SeatBelt) o.belt.emplace(m.seat_belt);
    if (m.rule == Rule::Below || m.rule == Rule::Above) o.hyst = Hysteresis{m.rule_on, m.rule_off, m.rule == Rule::Below};
    outs_.push_back(std::move(o));
  }
  if (mapping_.find(protocol::sig::kOdometer) && !mapping_.find(protocol::sig::kTrip)) {
    // The trip meter comes with the odometer.
    outputs_.push_back(ModelOutput{protocol::sig::kTrip});
  }
}

const ModelOutput* Model::output(protocol::SignalId id) const {
  for (const auto& o : outputs_)
    if (o.id == id) return &o;
  return nullptr;
}

std::optional<double> Model::true_speed() const {
  for (const auto& o : outs_)
    if (mapping_.outputs[o.map].id == protocol::sig::kSpeed) return o.truth_valid ? std::optional(o.truth) : std::nullopt;
  return std::nullopt;
}

std::vector<std::pair<std::uint32_t, bool>> Model::used_ids() const {
  std::vector<std::pair<std::uint32_t, bool>> ids;
  for (const auto& [m, t] : slots_by_message_) ids.emplace_back(m->id, m->extended);
  std::sort(ids.begin(), ids.end());
  return ids;
}

void Model::start(std::int64_t t) {
  start_ = t;
  last_update_ = t;
  last_persist_ = t;
  started_ = true;
  bulb_.start(t);
  for (auto& o : outs_)
    if (o.belt) o.belt->ignition_on(t);
}

void Model::on_frame(const CanFrame& f) {
  ++stats_.frames;
  if (f.error) {
    ++stats_.error_frames;
    return;
  }
  if (f.rtr || !db_) return;
  const DbcMessage* m = db_->find(f.id, f.extended);
  if (!m) {
    ++stats_.frames_unknown;
    return;
  }
  auto it = slots_by_message_.find(m);
  if (it == slots_by_message_.end()) return;
  ++stats_.frames_mapped;
  decode(*m, std::span<const std::uint8_t>(f.data.data(), f.len), scratch_);
  for (const auto& d : scratch_) {
    int si = it->second[static_cast<std::size_t>(d.signal)];
    if (si < 0) continue;
    Slot& s = slots_[static_cast<std::size_t>(si)];
    s.value = d.physical;
    s.raw = d.raw;
    s.status = d.status;
    s.valid = d.status == DecodeStatus::Valid || d.status == DecodeStatus::OutOfRange;
    s.received = true;
    s.last_rx = f.timestamp_ns;
    ++s.rx_count;
  }
}

void Model::on_value(std::string_view key, double value, bool valid, std::int64_t t) {
  ++stats_.values;
  auto it = slot_by_key_.find(std::string(key));
  if (it == slot_by_key_.end()) return;
  Slot& s = slots_[static_cast<std::size_t>(it->second)];
  s.valid = valid && std::isfinite(value);
  s.value = s.valid ? value : 0.0;
  s.status = s.valid ? DecodeStatus::Valid : DecodeStatus::NotFinite;
  s.received = true;
  s.last_rx = t;
  ++s.rx_count;
}

void Model::compute(Out& o, std::int64_t t, double dt) {
  const OutputMapping& m = mapping_.outputs[o.map];
  ModelOutput& out = outputs_[o.index];
  if (m.rule == Rule::Below || m.rule == Rule::Above) {
    const ModelOutput* in = output(protocol::find_signal(m.rule_input)->id);
    if (in && in->status == SignalStatus::Valid) {
      out.value = o.hyst->update(in->value) ? 1.0 : 0.0;
      out.status = SignalStatus::Valid;
    } else {
      out.value = 0;
      out.status = in ? in->status : SignalStatus::NotAvailable;
    }
    return;
  }
  // Gather the sources.
  int n_valid = 0, n_invalid = 0, n_timed_out = 0;
  double acc = 0;
  for (int si : o.slots) {
    const Slot& s = slots_[static_cast<std::size_t>(si)];
    if (!s.received) {
      if (o.first_timeout_ns >= 0 && t - start_ > o.first_timeout_ns) ++n_timed_out;
      continue;
    }
    if (o.timeout_ns >= 0 && t - s.last_rx > o.timeout_ns) {
      ++n_timed_out;
      continue;
    }
    double v = s.value;
    bool ok = s.valid;
    if (ok && s.status == DecodeStatus::OutOfRange) {
      if (m.out_of_range == RangeAction::Invalid) ok = false;
      else if (m.out_of_range == RangeAction::Clamp) v = std::clamp(v, s.dbc_min, s.dbc_max);
    }
    if (!ok) {
      ++n_invalid;
      continue;
    }
    if (n_valid == 0) acc = v;
    else if (m.combine == Combine::Mean) acc += v;
    else if (m.combine == Combine::Min) acc = std::min(acc, v);
    else if (m.combine == Combine::Max) acc = std::max(acc, v);
    ++n_valid;
    if (m.combine == Combine::First) break;
  }
  SignalStatus status;
  double value = 0;
  if (n_valid > 0) {
    if (m.combine == Combine::Mean) acc /= n_valid;
    value = acc * m.scale + m.offset;
    for (const auto& [from, to] : m.remap)
      if (std::fabs(value - from) < 1e-9) {
        value = to;
        break;
      }
    status = std::isfinite(value) ? SignalStatus::Valid : SignalStatus::Invalid;
    if (status != SignalStatus::Valid) value = 0;
  } else if (n_invalid > 0) {
    status = SignalStatus::Invalid;
  } else if (n_timed_out > 0) {
    status = SignalStatus::TimedOut;
  } else {
    status = SignalStatus::NotAvailable;
  }
  if (status == SignalStatus::TimedOut) {
    switch (m.on_timeout) {
      case TimeoutAction::Hold:
        if (o.has_good) {
          value = o.last_good;
          status = SignalStatus::Valid;
        }
        break;
      case TimeoutAction::Substitute:
        value = m.substitute;
        status = SignalStatus::Valid;
        break;
      case TimeoutAction::Invalid: value = o.last_good; break;
    }
  }
  o.truth = value;
  o.truth_valid = status == SignalStatus::Valid;
  if (o.truth_valid) {
    o.last_good = value;
    o.has_good = true;
  }

  // Conditioning.
  double shown = value;
  if (o.fuel) {
    auto speed = true_speed();
    o.fuel->step(value, o.truth_valid, speed.value_or(0.0), dt);
    if (o.fuel->fault()) {
      status = SignalStatus::Invalid;
      shown = 0;
    } else if (o.fuel->has_value()) {
      status = SignalStatus::Valid;
      shown = o.fuel->value();
    } else if (status == SignalStatus::Valid) {
      status = SignalStatus::NotAvailable;
    }
  } else if (o.needle && status == SignalStatus::Valid) {
    if (!o.was_valid) o.needle->reset(value);
    else o.needle->step(value, dt);
    shown = o.needle->value();
  }
  if (m.speedometer && status == SignalStatus::Valid) shown = m.speedometer->apply(shown, value);
  if (is_telltale(o.kind)) {
    bool req = status == SignalStatus::Valid && ((value != 0) != m.invert);
    if (req && !o.request) o.request_since = t;
    o.request = req;
    bool lit = req;
    if (o.belt) {
      auto speed = true_speed();
      lit = o.belt->lit(t, req, speed.value_or(0.0));
      if (status != SignalStatus::Valid) status = SignalStatus::Valid, lit = false;
    }
    if (m.blink && req) lit = m.blink->lit(t, o.request_since);
    shown = lit ? 1.0 : 0.0;
  }
  o.was_valid = status == SignalStatus::Valid;
  out.value = status == SignalStatus::Valid || status == SignalStatus::TimedOut ? shown : 0.0;
  out.status = status;
}

void Model::update(std::int64_t t) {
  if (!started_) start(t);
  double dt = updated_ ? static_cast<double>(t - last_update_) / 1e9 : 0.0;
  if (dt < 0) dt = 0;  // a log may step back in time: never integrate backwards
  const std::int64_t dt_ns = updated_ ? std::max<std::int64_t>(0, t - last_update_) : 0;
  for (auto& o : outs_) {
    const OutputMapping& m = mapping_.outputs[o.map];
    if (m.accumulate != Accumulate::None) continue;
    compute(o, t, dt);
    if (m.id == protocol::sig::kIgnition && o.truth_valid) {
      // Ignition on (VSS state ON or START) restarts the bulb check and the seat-belt timer.
      if (o.truth >= 4 && last_ignition_ >= 0 && last_ignition_ < 4) {
        bulb_.start(t);
        for (auto& b : outs_)
          if (b.belt) b.belt->ignition_on(t);
      } else if (o.truth < 4) {
        for (auto& b : outs_)
          if (b.belt) b.belt->ignition_off();
      }
      last_ignition_ = o.truth;
    }
  }
  // Odometer and trip.
  for (auto& o : outs_) {
    const OutputMapping& m = mapping_.outputs[o.map];
    if (m.accumulate == Accumulate::None) continue;
    if (m.accumulate == Accumulate::Speed) {
      if (auto v = true_speed()) odo_.add_speed(*v, dt_ns);
    } else if (!o.slots.empty()) {
      const Slot& s = slots_[static_cast<std::size_t>(o.slots[0])];
      if (s.received && s.valid && s.rx_count != o.counter_seen) {
        odo_.add_counter(s.raw, m.counter_bits, m.um_per_count);
        o.counter_seen = s.rx_count;
      }
    }
    outputs_[o.index].value = std::floor(odo_.total_km() * 10.0) / 10.0;  // odometers never round up
    outputs_[o.index].status = SignalStatus::Valid;
    for (auto& out : outputs_)
      if (out.id == protocol::sig::kTrip) {
        out.value = std::floor(odo_.trip_km() * 10.0) / 10.0;
        out.status = SignalStatus::Valid;
      }
  }
  // Bulb check: every mapped telltale lit, whatever its source says.
  if (bulb_.active(t))
    for (auto& o : outs_)
      if (is_telltale(o.kind)) {
        outputs_[o.index].value = 1.0;
        outputs_[o.index].status = SignalStatus::Valid;
      }
  if (store_ && t - last_persist_ >= static_cast<std::int64_t>(mapping_.persist_interval_s * 1e9)) {
    persist_now();
    last_persist_ = t;
  }
  last_update_ = t;
  updated_ = true;
}

void Model::persist_now() {
  if (!store_) return;
  try {
    store_->save(OdometerRecord{odo_.total_um(), odo_.trip_um(), ++persist_seq_});
    ++stats_.persist_saves;
  } catch (const std::exception&) {
    ++stats_.persist_errors;  // the next interval retries; the old file stays intact
  }
}

}  // namespace meter::controller
