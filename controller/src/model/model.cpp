#include "meter/controller/model/model.hpp"

#include <algorithm>
#include <cmath>

#include "meter/controller/mapping/signal_period.hpp"
#include "meter/controller/mapping/value_names.hpp"
#include "meter/protocol/signal_change.hpp"

namespace meter::controller {

using protocol::SignalKind;
using protocol::SignalStatus;

struct Model::Out {
  std::size_t map = 0;    // index into mapping_.outputs
  std::size_t index = 0;  // index into outputs_
  std::vector<int> sources;
  SourceTimeouts timeouts;
  OutputConditioner conditioner;
  std::optional<double> last_good;  // newest valid mapped value (timeout 'hold')
  double truth = 0;                 // mapped value before conditioning
  bool truth_valid = false;
  std::uint64_t counter_seen = 0;  // wheel-pulse counter: the source's rx_count last integrated
};

namespace {

// Evaluation order: speed first and ignition next (fuel, seat belt and the bulb check read them),
// plain signals, then threshold rules (they read shown values), then the odometer.
std::vector<std::size_t> evaluation_order(const Mapping& mapping) {
  auto rank = [&](std::size_t i) {
    const auto& o = mapping.outputs[i];
    if (o.name == protocol::vss::kSpeed) return 0;
    if (o.name == protocol::vss::kIgnition) return 1;
    if (o.rule == Rule::Below || o.rule == Rule::Above) return 3;
    if (o.accumulate != Accumulate::None) return 4;
    return 2;
  };
  std::vector<std::size_t> order(mapping.outputs.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return rank(a) < rank(b); });
  return order;
}

// VSS (vehicle system state) at or above this is ignition on (ON or START).
constexpr double kIgnitionOn = 4;

std::optional<protocol::SignalId> id_named(std::string_view name) {
  const auto* info = protocol::find_signal(name);
  return info ? std::optional<protocol::SignalId>(info->id) : std::nullopt;
}

bool maps(const Mapping& mapping, std::optional<protocol::SignalId> id) { return id && mapping.find(*id); }

}  // namespace

Model::Model(const Database* db, Mapping mapping, ModelOptions options)
    : Model(std::vector<InputDbc>{{"", db}}, std::move(mapping), std::move(options)) {}

Model::Model(std::vector<InputDbc> inputs, Mapping mapping, ModelOptions options)
    : mapping_(std::move(mapping)), options_(std::move(options)), sources_(std::move(inputs), mapping_),
      bulb_(mapping_.bulb_check_s) {
  special_ = {id_named(protocol::vss::kSpeed), id_named(protocol::vss::kIgnition), id_named(protocol::vss::kOdometer),
              id_named(protocol::vss::kTrip)};
  if (maps(mapping_, special_.odometer) && !special_.trip) {
    // The trip meter comes with the odometer: a catalog with one has the other.
    protocol::active_catalog()->require(protocol::vss::kTrip, "the trip meter that comes with the odometer");
  }
  resolve_value_names(mapping_, sources_.inputs());
  e2e_ = build_e2e_guard(sources_.inputs(), mapping_.e2e, mapping_.file);
  if (!e2e_.empty()) sources_.set_e2e(&e2e_);
  build_outputs();
  if (!options_.state_dir.empty() && maps(mapping_, special_.odometer)) {
    store_ = std::make_unique<OdometerStore>(options_.state_dir);
    const OdometerLoad loaded = store_->load();
    for (const std::string& fault : loaded.faults) report("odometer: " + fault);
    stats_.persist_faults = loaded.faults.size();
    stats_.odometer_refused = loaded.state == OdometerState::Refused;
    if (loaded.record) odo_.set(loaded.record->odo_um, loaded.record->trip_um);
  }
}

Model::~Model() = default;

void Model::build_outputs() {
  for (std::size_t i : evaluation_order(mapping_)) {
    const OutputMapping& m = mapping_.outputs[i];
    std::vector<int> sources = sources_.add(m);
    std::vector<std::optional<int>> cycles;
    for (int s : sources) {  // each source's own arrival period (a multiplexed page: its page's)
      const Source& src = sources_[s];
      cycles.push_back(src.dbc.message ? signal_period_ms(*src.dbc.message, src.dbc.signal) : src.cycle_ms);
    }
    const SourceTimeouts timeouts = derive_timeouts(m, cycles, mapping_.file);
    if (m.id == special_.speed && speed_out_ < 0) speed_out_ = static_cast<int>(outs_.size());
    outs_.push_back(Out{i, outputs_.size(), std::move(sources), timeouts,
                        OutputConditioner(m, protocol::find_signal(m.id)->kind), std::nullopt, 0.0, false, 0});
    outputs_.push_back(ModelOutput{m.id});
  }
  if (maps(mapping_, special_.odometer) && !maps(mapping_, special_.trip)) {
    // The trip meter comes with the odometer.
    outputs_.push_back(ModelOutput{*special_.trip});
  }
}

const ModelOutput* Model::output(protocol::SignalId id) const {
  for (const auto& o : outputs_)
    if (o.id == id) return &o;
  return nullptr;
}

std::optional<double> Model::true_speed() const {
  if (speed_out_ < 0) return std::nullopt;
  const Out& o = outs_[static_cast<std::size_t>(speed_out_)];
  return o.truth_valid ? std::optional(o.truth) : std::nullopt;
}

std::optional<double> Model::speed_estimate() const {
  if (speed_out_ < 0) return std::nullopt;
  return outs_[static_cast<std::size_t>(speed_out_)].conditioner.speed_estimate();
}

std::vector<std::pair<std::uint32_t, bool>> Model::used_ids(int input) const {
  std::vector<std::pair<std::uint32_t, bool>> ids = sources_.used_ids(input);
  // A protected message is checked (and counted) even when no output reads it.
  for (const auto& e : e2e_.entries())
    if (e.message.input == input) ids.emplace_back(e.message.message->id, e.message.message->extended);
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

void Model::start(std::int64_t t) {
  start_ = t;
  last_update_ = t;
  last_persist_ = t;
  started_ = true;
  bulb_.start(t);
  for (auto& o : outs_) o.conditioner.ignition_on(t);
}

void Model::on_frame(const CanFrame& f) {
  ++stats_.frames;
  switch (sources_.on_frame(f)) {
    case FrameUse::ErrorFrame: ++stats_.error_frames; break;
    case FrameUse::UnknownId: ++stats_.frames_unknown; break;
    case FrameUse::Mapped: ++stats_.frames_mapped; break;
    case FrameUse::Refused: ++stats_.frames_refused; break;
    case FrameUse::Ignored:
    case FrameUse::Unused: break;
  }
}

void Model::on_value(std::string_view key, double value, bool valid, std::int64_t t) {
  ++stats_.values;
  sources_.on_value(key, value, valid, t);
}

void Model::evaluate(Out& o, std::int64_t t, double dt) {
  const OutputMapping& m = mapping_.outputs[o.map];
  ModelOutput& out = outputs_[o.index];
  OutputValue shown;
  if (o.conditioner.threshold_rule()) {
    std::optional<OutputValue> watched;
    if (const ModelOutput* in = output(protocol::find_signal(m.rule_input)->id)) watched = OutputValue{in->value, in->status};
    shown = o.conditioner.threshold(watched);
  } else {
    readings_.clear();
    for (int s : o.sources) readings_.push_back(sources_[s].reading);
    const OutputValue mapped = map_output(m, readings_, o.timeouts, t, start_, o.last_good);
    o.truth = mapped.value;
    o.truth_valid = mapped.status == SignalStatus::Valid;
    if (o.truth_valid) o.last_good = mapped.value;
    shown = o.conditioner.condition(mapped, t, dt, true_speed());
  }
  out.value = shown.value;
  out.status = shown.status;
}

void Model::on_ignition(double vss_state, std::int64_t t) {
  // Ignition on restarts the bulb check and the seat-belt timer.
  if (vss_state >= kIgnitionOn && last_ignition_ >= 0 && last_ignition_ < kIgnitionOn) {
    bulb_.start(t);
    for (auto& b : outs_) b.conditioner.ignition_on(t);
  } else if (vss_state < kIgnitionOn) {
    for (auto& b : outs_) b.conditioner.ignition_off();
  }
  last_ignition_ = vss_state;
}

void Model::accumulate_distance(Out& o, std::int64_t dt_ns) {
  const OutputMapping& m = mapping_.outputs[o.map];
  if (m.accumulate == Accumulate::Speed) {
    if (auto v = true_speed()) odo_.add_speed(*v, dt_ns);
  } else if (!o.sources.empty()) {
    const Source& s = sources_[o.sources[0]];
    if (s.reading.received && s.reading.valid && s.rx_count != o.counter_seen) {
      odo_.add_counter(s.raw, m.counter_bits, m.um_per_count);
      o.counter_seen = s.rx_count;
    }
  }
  // A refused odometer state (damaged, or put back from an older state) shows the failsafe look
  // instead of a distance that could be behind the truth.
  const bool ok = !stats_.odometer_refused;
  const SignalStatus status = ok ? SignalStatus::Valid : SignalStatus::Invalid;
  outputs_[o.index].value = ok ? odometer_display_km(odo_.total_km()) : 0.0;
  outputs_[o.index].status = status;
  for (auto& out : outputs_)
    if (out.id == special_.trip) {
      out.value = ok ? odometer_display_km(odo_.trip_km()) : 0.0;
      out.status = status;
    }
}

void Model::update(std::int64_t t) {
  if (!started_) start(t);
  double dt = updated_ ? static_cast<double>(t - last_update_) / 1e9 : 0.0;
  if (dt < 0) dt = 0;  // a log may step back in time: never integrate backwards
  const std::int64_t dt_ns = updated_ ? std::max<std::int64_t>(0, t - last_update_) : 0;
  for (auto& o : outs_) {
    const OutputMapping& m = mapping_.outputs[o.map];
    if (m.accumulate != Accumulate::None) continue;
    evaluate(o, t, dt);
    if (m.id == special_.ignition && o.truth_valid) on_ignition(o.truth, t);
  }
  for (auto& o : outs_)
    if (mapping_.outputs[o.map].accumulate != Accumulate::None) accumulate_distance(o, dt_ns);
  // Bulb check: every mapped telltale lit, whatever its source says.
  if (bulb_.active(t))
    for (auto& o : outs_)
      if (o.conditioner.telltale()) {
        outputs_[o.index].value = 1.0;
        outputs_[o.index].status = SignalStatus::Valid;
      }
  if (store_ && t - last_persist_ >= static_cast<std::int64_t>(mapping_.persist_interval_s * 1e9)) {
    persist_now();
    last_persist_ = t;
  }
  last_update_ = t;
  updated_ = true;
  detect_changes();
}

void Model::detect_changes() {
  changed_.clear();
  const bool first = reported_.size() != outputs_.size();
  // The link's own rule (signal_change.hpp): a change here is exactly what the Publisher's table
  // will count as one, so every listed output reaches the view and no unlisted one differs.
  for (std::size_t i = 0; i < outputs_.size(); ++i)
    if (first || protocol::signal_changed(reported_[i].value, reported_[i].status, outputs_[i].value, outputs_[i].status))
      changed_.push_back(i);
  reported_ = outputs_;
}

void Model::persist_now() {
  if (!store_ || stats_.odometer_refused) return;
  try {
    store_->save(odo_.total_um(), odo_.trip_um());
    ++stats_.persist_saves;
    if (persist_failing_) report("odometer: saving works again");
    persist_failing_ = false;
  } catch (const std::exception& e) {
    // The next interval retries; both stored copies stay as they were. Reported once per spell.
    ++stats_.persist_errors;
    if (!persist_failing_) report(std::string("odometer: save failed, retrying every interval: ") + e.what());
    persist_failing_ = true;
  }
}

void Model::report(const std::string& line) const {
  if (options_.report) options_.report(line);
}

}  // namespace meter::controller
