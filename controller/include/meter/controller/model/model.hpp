// The cluster signal model: bus values in, catalog values out. Pure and time-stepped: frames and
// register values go in with on_frame()/on_value(), update(t) advances timeouts and conditioning to
// time t, outputs() holds what the view should show and changed() which of them the tick changed.
// No sockets, no clocks of its own. It only ties the stages together, in order: the source table
// and mapping application (mapping/), conditioning (conditioning/), odometer persistence
// (persistence/).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "meter/controller/conditioning/odometer.hpp"
#include "meter/controller/conditioning/output_conditioner.hpp"
#include "meter/controller/conditioning/telltales.hpp"
#include "meter/controller/dbc/database.hpp"
#include "meter/controller/e2e/e2e_guard.hpp"
#include "meter/controller/input/can_frame.hpp"
#include "meter/controller/mapping/apply.hpp"
#include "meter/controller/mapping/mapping.hpp"
#include "meter/controller/mapping/sources.hpp"
#include "meter/controller/persistence/odometer_store.hpp"
#include "meter/protocol/catalog.hpp"

namespace meter::controller {

struct ModelOutput {
  protocol::SignalId id;
  double value = 0.0;
  protocol::SignalStatus status = protocol::SignalStatus::NotAvailable;
};

struct ModelStats {
  std::uint64_t frames = 0;           // frames offered
  std::uint64_t frames_mapped = 0;    // frames of a message the mapping uses
  std::uint64_t frames_unknown = 0;   // id not in the DBC
  std::uint64_t frames_refused = 0;   // a protected message's frame that failed its E2E check
  std::uint64_t error_frames = 0;
  std::uint64_t values = 0;           // register values offered
  std::uint64_t persist_saves = 0;
  std::uint64_t persist_errors = 0;   // failed saves (each retried at the next interval)
  std::uint64_t persist_faults = 0;   // damaged or contradicting odometer copies found at start
  bool odometer_refused = false;      // no trustworthy odometer state: shown invalid, not written
};

struct ModelOptions {
  std::string state_dir;  // empty: odometer not persisted
  // Where faults are reported (a damaged odometer copy, a failing save and its recovery), one line
  // each; empty: not reported (the stats still count them).
  std::function<void(const std::string&)> report = nullptr;
};

class Model {
 public:
  // db may be null for Modbus-only mappings. Throws MappingError when the mapping names a DBC
  // signal that does not exist, 'timeout = auto' for a message without a cycle time, or an
  // [e2e MESSAGE] that does not resolve.
  Model(const Database* db, Mapping mapping, ModelOptions options = {});
  // Several inputs (buses), each with its own DBC or none; frames carry their input's index.
  Model(std::vector<InputDbc> inputs, Mapping mapping, ModelOptions options = {});
  ~Model();
  Model(const Model&) = delete;
  Model& operator=(const Model&) = delete;

  void start(std::int64_t t_ns);  // first timeouts and the bulb check run from here
  void on_frame(const CanFrame& frame);
  // A non-CAN source value ("modbus.NAME"); valid=false marks it unusable (timeout, exception).
  void on_value(std::string_view key, double value, bool valid, std::int64_t t_ns);
  void update(std::int64_t t_ns);
  void persist_now();  // saves the odometer if a state dir is set (also done every persist interval)

  const std::vector<ModelOutput>& outputs() const { return outputs_; }
  // Indices into outputs() whose value or status the last update() changed (all of them after
  // the first), by the link's own rule (protocol::signal_changed: the value's bits, then the
  // status): the run loop publishes and traces only these.
  const std::vector<std::size_t>& changed() const { return changed_; }
  const ModelOutput* output(protocol::SignalId id) const;
  const ModelStats& stats() const { return stats_; }
  const Mapping& mapping() const { return mapping_; }
  // The end-to-end checks of the protected messages (the map's [e2e] sections), with their counts.
  const E2eGuard& e2e() const { return e2e_; }
  const Odometer& odometer() const { return odo_; }
  // True speed (before damping and the R39 rule), for tests and the odometer.
  std::optional<double> true_speed() const;
  // The speedometer's estimate of the true speed, which its UN R39 band is held around (nullopt: no
  // speedometer rule, or no valid speed).
  std::optional<double> speed_estimate() const;
  // The messages the mapping uses on that input, and those its [e2e] sections protect (SocketCAN
  // kernel filters use the ids).
  std::vector<std::pair<std::uint32_t, bool>> used_ids(int input = 0) const;

 private:
  struct Out;
  void build_outputs();
  void evaluate(Out& o, std::int64_t t, double dt);
  void accumulate_distance(Out& o, std::int64_t dt_ns);
  void on_ignition(double vss_state, std::int64_t t);
  void detect_changes();
  void report(const std::string& line) const;

  Mapping mapping_;
  ModelOptions options_;
  SourceTable sources_;
  E2eGuard e2e_;
  std::vector<Out> outs_;
  // Ids of the signals the model treats specially, found by VSS name in the loaded catalog
  // (another catalog may number them differently); nullopt when the catalog has none.
  struct SpecialIds {
    std::optional<protocol::SignalId> speed, ignition, odometer, trip;
  } special_;
  int speed_out_ = -1;  // the vehicle-speed output in outs_ (the odometer and conditioning read it), -1 = none
  std::vector<ModelOutput> outputs_;
  std::vector<ModelOutput> reported_;  // outputs as of the previous update (change detection)
  std::vector<std::size_t> changed_;
  std::vector<SourceReading> readings_;  // scratch: one output's source readings
  ModelStats stats_;
  Odometer odo_;
  std::unique_ptr<OdometerStore> store_;
  bool persist_failing_ = false;  // the last save failed (reported once, and again when it recovers)
  std::int64_t last_persist_ = 0;
  BulbCheck bulb_;
  std::int64_t start_ = 0, last_update_ = 0;
  bool started_ = false, updated_ = false;
  double last_ignition_ = -1;
};

}  // namespace meter::controller
