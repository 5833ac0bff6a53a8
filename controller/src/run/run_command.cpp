// run: the daemon loop. Input -> model (sources, mapping, conditioning) -> publisher, ticking the
// model every update period of input time and never waiting for a view.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <memory>
#include <optional>
#include <ostream>

#include "command_output.hpp"
#include "health_report.hpp"
#include "latency_trace.hpp"
#include "meter/controller/dbc/database.hpp"
#include "meter/controller/e2e/e2e_guard.hpp"
#include "meter/controller/input/input.hpp"
#include "meter/controller/input/socketcan.hpp"
#include "meter/controller/mapping/mapping.hpp"
#include "meter/controller/model/model.hpp"
#include "meter/controller/run/input_specs.hpp"
#include "meter/controller/run/run_command.hpp"
#include "meter/protocol/link.hpp"
#include "meter/protocol/link_stats_text.hpp"
#include "meter/protocol/trace_events.hpp"
#include "open_input.hpp"
#include "publish_recording.hpp"
#include "service_notify.hpp"
#include "meter/protocol/log/logger.hpp"

namespace meter::controller {
namespace {

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

class ModelSink : public InputSink {
 public:
  ModelSink(Model& m, Trace& t, protocol::TraceEventFile& events) : m_(m), t_(t), events_(events) {}
  void on_frame(const CanFrame& f) override {
    const std::int64_t begin = events_.on() ? protocol::monotonic_now_ns() : 0;
    m_.on_frame(f);
    t_.frame(f);
    if (events_.on()) events_.complete("decode", "controller", begin, protocol::monotonic_now_ns(), 1,
                                       {{"can_id", static_cast<std::int64_t>(f.id)}});
  }
  void on_value(std::string_view key, double v, bool valid, std::int64_t t) override { m_.on_value(key, v, valid, t); }

 private:
  Model& m_;
  Trace& t_;
  protocol::TraceEventFile& events_;
};

// Every input's DBC (none: empty), loaded as the specs name them; warnings go to err.
std::vector<std::optional<Database>> load_dbcs(const std::vector<InputSpec>& specs, bool strict, std::ostream& err) {
  std::vector<std::optional<Database>> dbs(specs.size());
  for (std::size_t i = 0; i < specs.size(); ++i) {
    if (specs[i].dbc.empty()) continue;
    dbs[i] = load_dbc(specs[i].dbc, DbcOptions{strict});
    report_dbc_warnings(*dbs[i], err);
  }
  return dbs;
}

// The model's view of the inputs: each one's name and DBC.
std::vector<InputDbc> input_dbcs(const std::vector<InputSpec>& specs, const std::vector<std::optional<Database>>& dbs) {
  std::vector<InputDbc> buses;
  for (std::size_t i = 0; i < specs.size(); ++i) buses.push_back(InputDbc{specs[i].name, dbs[i] ? &*dbs[i] : nullptr});
  return buses;
}

// The outputs a tick changed (the model says which), and only those, to the link, the latency
// trace and the --record file: a SNAPSHOT for the first tick (it changes every output), DELTAs after.
class ChangePublisher {
 public:
  ChangePublisher(const Model& model, protocol::Publisher& pub, Trace& trace, PublishRecording& recording)
      : model_(model), pub_(pub), trace_(trace), recording_(recording) {}
  void operator()(std::int64_t t) {
    const auto& outs = model_.outputs();
    std::vector<protocol::SignalUpdate> recorded;
    for (std::size_t i : model_.changed()) {
      pub_.set(outs[i].id, outs[i].value, outs[i].status);
      trace_.publish(static_cast<int>(outs[i].id), outs[i].value);
      if (recording_.on()) recorded.push_back(protocol::SignalUpdate{outs[i].id, outs[i].status, outs[i].value, false, {}});
    }
    if (recording_.on()) {
      const bool first = model_.changed().size() == outs.size() && !recorded_any_;
      recorded_any_ = true;
      if (first) recording_.snapshot(t, std::move(recorded));
      else recording_.delta(t, std::move(recorded));
    }
  }

 private:
  const Model& model_;
  protocol::Publisher& pub_;
  Trace& trace_;
  PublishRecording& recording_;
  bool recorded_any_ = false;
};

// The inputs' health with the model's E2E counts to the report: `e2e`, kept by the caller across
// ticks, is updated in place and lent to the report's BusHealth for the call (no allocation).
void update_health(HealthReport& health, const Input& input, const Model& model, std::vector<E2eHealth>& e2e,
                   std::uint32_t view_faults, std::int64_t t, std::ostream& err, Trace& trace) {
  BusHealth bus = input.health();
  update_e2e_health(model.e2e(), e2e);
  bus.e2e.swap(e2e);
  health.update(bus, view_faults, t, err, trace);
  bus.e2e.swap(e2e);  // back, for the next tick
}

// The final stats line: frames, link traffic, the odometer and its store, the bus health.
void print_stats(std::ostream& out, const Model& model, const protocol::Publisher& pub, const HealthReport& health) {
  const auto& st = model.stats();
  auto ls = pub.stats();
  out << "meter-controller: " << st.frames << " frames (" << st.frames_mapped << " mapped, " << st.frames_unknown
      << " unknown id, " << st.error_frames << " error frames"
      << (model.e2e().empty() ? "" : ", " + std::to_string(st.frames_refused) + " refused by e2e checks") << "), " << st.values << " register values, "
      << ls.deltas_sent << " deltas / " << ls.snapshots_sent << " snapshots sent, odometer "
      << fmt_double(model.odometer().total_km()) << " km" << (st.odometer_refused ? " (invalid: stored state refused)" : "")
      << ", " << st.persist_faults << " damaged odometer copies, " << st.persist_errors << " odometer save errors, "
      << health.stats_text() << "\n";
  out << "meter-controller: link: " << protocol::link_stats_text(ls) << "\n";
}

}  // namespace

int run_command(const RunOptions& o, std::ostream& out, std::ostream& err) {
  g_stop = 0;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::signal(SIGPIPE, SIG_IGN);
  try {
    protocol::use_catalog_option(o.catalog);  // before the mapping: its sections name catalog signals
    const std::vector<InputSpec> specs = parse_input_specs(o.inputs, o.dbcs);
    const std::vector<std::optional<Database>> dbs = load_dbcs(specs, o.strict, err);
    Mapping map = load_mapping(o.map);
    Model model(input_dbcs(specs, dbs), map,
                ModelOptions{o.state_dir, [&err](const std::string& line) { protocol::LogLine(err, protocol::LogLevel::Warning, "model") << "meter-controller: " << line; }});

    std::unique_ptr<Input> input;
    try {
      input = open_inputs(specs, dbs, o.replay, map, model, err);
    } catch (const SocketCanError& e) {
      protocol::LogLine(err, protocol::LogLevel::Error, "input") << "meter-controller: " << e.what() << "\n";
      return 3;
    }

    protocol::LinkOptions lo = protocol::link_options("meter-controller", std::chrono::milliseconds(o.link_timeout_ms));
    lo.key_file = o.key_file;
    lo.insecure_link = o.insecure_link;
    Trace trace(o.trace);
    // --trace-json: receive (an input poll that delivered frames), decode (per frame, inside it),
    // condition (the model's tick), publish (changed outputs handed to the link and flushed: the
    // DELTA's sender stamp falls inside it), on CLOCK_MONOTONIC.
    protocol::TraceEventFile events(o.trace_json, "meter-controller");
    events.thread_name(1, "controller loop");
    protocol::Publisher pub(protocol::endpoint_from_option(o.link), lo);
    ControllerService service(err);  // the service manager: ready, keep-alives, stopping (docs/deploy.md)
    service.listening(pub.endpoint().to_string());
    if (o.verbose) protocol::LogLine(err, protocol::LogLevel::Info, "run", {protocol::log_field("input", input->describe())}) << "meter-controller: " << input->describe() << " -> " << pub.endpoint().to_string() << "\n";

    // --record: the same changes on the input's clock (the first tick changes every output: a SNAPSHOT).
    PublishRecording recording(o.record);
    ChangePublisher publish(model, pub, trace, recording);

    ModelSink sink(model, trace, events);
    HealthReport health(input->describe());
    std::vector<E2eHealth> e2e;  // kept across ticks: named once, its counts rewritten in place
    auto report_health = [&](std::int64_t t) {
      update_health(health, *input, model, e2e, view_fault_flags(pub.peer_status()), t, err, trace);
      const std::uint64_t lost = health.bus().kernel_drops + health.bus().interface_drops;
      pub.send_status(model.stats().frames + model.stats().values, lost, health.controller_faults());
      recording.status(t, model.stats().frames + model.stats().values, lost, health.controller_faults());
    };
    std::uint64_t traced_bytes = 0;
    // The model ticks every update period of input time; inputs are polled until the next tick.
    const auto period_ns = static_cast<std::int64_t>(map.update_period_s * 1e9);
    model.start(input->now_ns());
    std::int64_t next_tick = input->now_ns() + period_ns;
    // After the end of a log (without --exit-at-end) the loop runs on: the input is a silent bus and
    // the model's timeouts expire as on a live one.
    bool more = true, ended = false;
    while (!g_stop && !(ended && o.exit_at_end)) {
      service.alive();
      const double wait_wall_ns = static_cast<double>(next_tick - input->now_ns()) / input->rate();
      // Rounded up: a 0 ms wait while the tick is still ahead would spin.
      const auto wait = std::chrono::milliseconds(std::clamp<std::int64_t>(static_cast<std::int64_t>(std::ceil(wait_wall_ns / 1e6)), 1, 100));
      const std::uint64_t frames_before = model.stats().frames;
      const std::int64_t poll_begin = events.on() ? protocol::monotonic_now_ns() : 0;
      more = input->poll(sink, wait);
      const std::int64_t poll_end = events.on() ? protocol::monotonic_now_ns() : 0;
      if (model.stats().frames != frames_before) {
        events.complete("receive", "controller", poll_begin, poll_end, 1,
                        {{"frames", static_cast<std::int64_t>(model.stats().frames - frames_before)}});
      }
      const bool just_ended = !more && !ended;
      ended = !more;
      const std::int64_t t = input->now_ns();
      const bool tick = t >= next_tick || just_ended;
      std::size_t changed = 0;
      std::int64_t conditioned = 0;
      if (tick) {
        model.update(t);
        changed = model.changed().size();
        conditioned = events.on() ? protocol::monotonic_now_ns() : 0;
        events.complete("condition", "controller", poll_end, conditioned, 1);
        publish(t);
        report_health(t);
        next_tick = std::max(next_tick + period_ns, t);  // no catch-up burst after a stall
      }
      pub.poll(std::chrono::milliseconds(0));  // never waits for a view
      if (tick && changed > 0) {
        events.complete("publish", "controller", conditioned, protocol::monotonic_now_ns(), 1,
                        {{"changed", static_cast<std::int64_t>(changed)}});
      }
      if (trace.on()) {
        const auto ls = pub.stats();
        if (ls.bytes_sent != traced_bytes) trace.sent(traced_bytes = ls.bytes_sent, ls.deltas_sent);
      }
    }
    model.persist_now();
    trace.flush();
    recording.close();
    if (!events.close()) protocol::LogLine(err, protocol::LogLevel::Error, "trace", {protocol::log_field("file", o.trace_json)}) << "meter-controller: write error on " << o.trace_json << "\n";
    if (o.verbose) {
      for (const auto& x : model.outputs())
        err << "  final " << protocol::find_signal(x.id)->name << " = " << fmt_double(x.value) << " ("
            << protocol::to_string(x.status) << ")\n";
    }
    if (!g_stop && o.linger_s > 0) {
      const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(o.linger_s);
      while (!g_stop && std::chrono::steady_clock::now() < until) {
        service.alive();
        pub.poll(std::chrono::milliseconds(20));
        report_health(input->now_ns());
      }
    }
    service.stopping();
    print_stats(out, model, pub, health);
    return 0;
  } catch (const std::exception& e) {
    protocol::LogLine(err, protocol::LogLevel::Error, "run") << "meter-controller: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace meter::controller
