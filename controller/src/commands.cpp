#include "meter/controller/commands.hpp"

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <ostream>
#include <fstream>
#include <set>
#include <thread>
#include <time.h>

#include "meter/controller/dbc.hpp"
#include "meter/controller/input.hpp"
#include "meter/controller/mapping.hpp"
#include "meter/controller/model.hpp"
#include "meter/protocol/link.hpp"

namespace meter::controller {
namespace {

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

// --trace: one CSV line per pipeline event, so the time from a frame's kernel receive timestamp to
// the link can be split by stage offline (bench/latency). Rows:
//   f,<t_ns>,<frame_ts_ns>,<can id>             the model has decoded the frame (ts: kernel stamp on can:)
//   p,<t_ns>,<signal id>,<value>                a changed output handed to the publisher
//   s,<t_ns>,<bytes sent total>,<deltas total>  the link wrote bytes to the socket
//   c,<t_ns>,<CLOCK_MONOTONIC ns>,              once: maps the link's send stamps onto t_ns
// Buffered in memory-sized blocks: the controller's loop must not wait for a disk (or a 9p share).
class Trace {
 public:
  explicit Trace(const std::string& path) {
    if (path.empty()) return;
    out_.rdbuf()->pubsetbuf(buf_.data(), static_cast<std::streamsize>(buf_.size()));
    out_.open(path);
    if (!out_) throw std::runtime_error(path + ": cannot write the trace");
    out_ << "event,t_ns,a,b\n";
    // The link's frames carry CLOCK_MONOTONIC send stamps: this pair maps them onto the trace.
    timespec mono;
    clock_gettime(CLOCK_MONOTONIC, &mono);
    out_ << "c," << realtime_ns() << "," << static_cast<std::int64_t>(mono.tv_sec) * 1000000000LL + mono.tv_nsec << ",\n";
  }
  bool on() const { return out_.is_open(); }
  void frame(const CanFrame& f) {
    if (on()) out_ << "f," << realtime_ns() << "," << f.timestamp_ns << "," << f.id << "\n";
  }
  void publish(int id, double v) {
    if (on()) out_ << "p," << realtime_ns() << "," << id << "," << fmt(v) << "\n";
  }
  void sent(std::uint64_t bytes, std::uint64_t deltas) {
    if (on()) out_ << "s," << realtime_ns() << "," << bytes << "," << deltas << "\n";
  }
  void flush() {
    if (on()) out_.flush();
  }

 private:
  static std::string fmt(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.9g", v);
    return b;
  }
  std::vector<char> buf_ = std::vector<char>(1 << 20);
  std::ofstream out_;
};

class ModelSink : public InputSink {
 public:
  ModelSink(Model& m, Trace& t) : m_(m), t_(t) {}
  void on_frame(const CanFrame& f) override {
    m_.on_frame(f);
    t_.frame(f);
  }
  void on_value(std::string_view key, double v, bool valid, std::int64_t t) override { m_.on_value(key, v, valid, t); }

 private:
  Model& m_;
  Trace& t_;
};

std::string csv_field(std::string_view s) {
  if (s.find_first_of(",\"\n") == std::string_view::npos) return std::string(s);
  std::string o = "\"";
  for (char c : s) {
    if (c == '"') o += '"';
    o += c;
  }
  return o + "\"";
}

std::string fmt_double(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.15g", v);
  return buf;
}

void report_bad_lines(const ParsedLog& log, const std::string& path, std::ostream& err) {
  if (log.bad_lines.empty()) return;
  err << path << ": skipped " << log.bad_lines.size() << " bad line(s)\n";
  std::size_t shown = 0;
  for (const auto& b : log.bad_lines) {
    if (++shown > 10) {
      err << "  ... and " << log.bad_lines.size() - 10 << " more\n";
      break;
    }
    err << "  " << path << ":" << b.line << ": " << b.why << "\n";
  }
}

}  // namespace

int decode_command(const std::string& dbc_path, const std::string& log_path, const std::string& map_path,
                   std::ostream& out, std::ostream& err) {
  try {
    Database db = load_dbc(dbc_path);
    std::set<std::pair<const DbcMessage*, int>> wanted;
    if (!map_path.empty()) {
      Mapping map = load_mapping(map_path);
      Model check(&db, map);  // validates every source against the DBC
      for (const auto& o : map.outputs)
        for (const auto& s : o.sources) {
          if (s.rfind("modbus.", 0) == 0) continue;
          auto dot = s.find('.');
          const DbcMessage* m = db.find(s.substr(0, dot));
          wanted.emplace(m, m->find_signal(s.substr(dot + 1)));
        }
    }
    ParsedLog log = load_candump_log(log_path);
    report_bad_lines(log, log_path, err);
    out << "timestamp,message,signal,raw,physical,unit,status\n";
    std::vector<DecodedSignal> decoded;
    std::uint64_t unknown = 0;
    std::string row;
    for (const auto& f : log.frames) {
      if (f.error || f.rtr) continue;
      const DbcMessage* m = db.find(f.id, f.extended);
      if (!m) {
        ++unknown;
        continue;
      }
      decode(*m, std::span<const std::uint8_t>(f.data.data(), f.len), decoded);
      char ts[32];
      std::snprintf(ts, sizeof ts, "%lld.%06lld", static_cast<long long>(f.timestamp_ns / 1000000000LL),
                    static_cast<long long>((f.timestamp_ns % 1000000000LL) / 1000));
      for (const auto& d : decoded) {
        if (!wanted.empty() && !wanted.count({m, d.signal})) continue;
        const DbcSignal& s = m->signals[static_cast<std::size_t>(d.signal)];
        row.clear();
        row += ts;
        row += ',';
        row += m->name;
        row += ',';
        row += s.name;
        row += ',';
        if (s.value_type == ValueType::Integer && s.is_signed) row += std::to_string(d.raw_signed());
        else row += std::to_string(d.raw);
        row += ',';
        row += d.status == DecodeStatus::NotFinite ? std::string() : fmt_double(d.physical);
        row += ',';
        row += csv_field(s.unit);
        row += ',';
        row += to_string(d.status);
        row += '\n';
        out << row;
      }
    }
    if (unknown) err << log_path << ": " << unknown << " frame(s) with ids the DBC does not define\n";
    return 0;
  } catch (const std::exception& e) {
    err << "meter-controller decode: " << e.what() << "\n";
    return 1;
  }
}

int check_dbc_command(const std::string& dbc_path, std::ostream& out, std::ostream& err) {
  Database db;
  try {
    db = load_dbc(dbc_path);
  } catch (const DbcError& e) {
    err << e.what() << "\n";
    return 1;
  }
  std::size_t signals = 0, mux = 0, floats = 0, with_cycle = 0, j1939 = 0, ext = 0, motorola = 0, intel = 0, tables = 0;
  for (const auto& m : db.messages) {
    signals += m.signals.size();
    with_cycle += m.cycle_time_ms.has_value();
    j1939 += m.j1939;
    ext += m.extended;
    for (const auto& s : m.signals) {
      mux += s.is_multiplexor || s.mux_switch >= 0;
      floats += s.value_type != ValueType::Integer;
      (s.little_endian ? intel : motorola)++;
      tables += !s.choices.empty();
    }
  }
  out << dbc_path << ": DBC version \"" << db.version << "\", " << db.nodes.size() << " node(s), " << db.messages.size()
      << " message(s), " << signals << " signal(s)\n";
  out << "  extended ids: " << ext << ", J1939 (PGN matched): " << j1939 << ", with GenMsgCycleTime: " << with_cycle
      << "\n  signals: " << intel << " Intel, " << motorola << " Motorola, " << mux << " multiplexing, " << floats
      << " IEEE float, " << tables << " with value tables\n";
  for (const auto& m : db.messages) {
    char id[24];
    std::snprintf(id, sizeof id, m.extended ? "0x%08X" : "0x%03X", m.id);
    out << "  " << id << " " << m.name << " " << int(m.size) << " bytes, "
        << (m.cycle_time_ms ? std::to_string(*m.cycle_time_ms) + " ms" : std::string("no cycle time")) << ", "
        << m.signals.size() << " signal(s)\n";
  }
  if (db.warnings.empty()) {
    out << "  no problems found\n";
  } else {
    out << "  " << db.warnings.size() << " problem(s):\n";
    for (const auto& w : db.warnings) out << "    " << dbc_path << ":" << w.line << ": " << w.text << "\n";
  }
  return 0;
}

int run_command(const RunOptions& o, std::ostream& out, std::ostream& err) {
  g_stop = 0;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::signal(SIGPIPE, SIG_IGN);
  try {
    std::optional<Database> db;
    if (!o.dbc.empty()) db = load_dbc(o.dbc);
    Mapping map = load_mapping(o.map);
    Model model(db ? &*db : nullptr, map, ModelOptions{o.state_dir});

    std::unique_ptr<Input> input;
    if (o.input.rfind("log:", 0) == 0) {
      std::string path = o.input.substr(4);
      ParsedLog log = load_candump_log(path);
      report_bad_lines(log, path, err);
      if (log.frames.empty()) throw std::runtime_error(path + ": no frames in the log");
      input = std::make_unique<LogReplay>(std::move(log), parse_replay(o.replay));
    } else if (o.input.rfind("can:", 0) == 0) {
      std::vector<std::pair<std::uint32_t, bool>> ids = model.used_ids();
      // J1939 messages are matched by PGN (any source address): no exact kernel filter then.
      if (db)
        for (const auto& m : db->messages)
          if (m.j1939) ids.clear();
      try {
        input = std::make_unique<SocketCanInput>(o.input.substr(4), ids);
      } catch (const SocketCanError& e) {
        err << "meter-controller: " << e.what() << "\n";
        return 3;
      }
    } else if (o.input.rfind("modbus-tcp:", 0) == 0 || o.input.rfind("modbus-rtu:", 0) == 0) {
      if (!map.modbus) throw std::runtime_error(o.map + ": a Modbus input needs a [modbus] section with registers");
      input = std::make_unique<ModbusInput>(o.input.substr(7), *map.modbus);
    } else {
      throw std::invalid_argument("--input: expected log:FILE, can:IFACE, modbus-tcp:HOST:PORT or modbus-rtu:DEV:BAUD, got '" + o.input + "'");
    }

    const protocol::LinkOptions lo =
        protocol::link_options("meter-controller", std::chrono::milliseconds(o.link_timeout_ms));
    Trace trace(o.trace);
    protocol::Publisher pub(protocol::endpoint_from_option(o.link), lo);
    if (o.verbose) err << "meter-controller: " << input->describe() << " -> " << pub.endpoint().to_string() << "\n";

    struct Last {
      double v;
      protocol::SignalStatus s;
      bool sent;
    };
    std::vector<Last> last(model.outputs().size(), Last{0, protocol::SignalStatus::NotAvailable, false});
    auto publish = [&] {
      const auto& outs = model.outputs();
      for (std::size_t i = 0; i < outs.size(); ++i) {
        if (last[i].sent && last[i].v == outs[i].value && last[i].s == outs[i].status) continue;
        pub.set(outs[i].id, outs[i].value, outs[i].status);
        trace.publish(static_cast<int>(outs[i].id), outs[i].value);
        last[i] = {outs[i].value, outs[i].status, true};
      }
    };

    ModelSink sink(model, trace);
    std::uint64_t traced_bytes = 0;
    // The model ticks every update period of input time; inputs are polled until the next tick.
    const auto period_ns = static_cast<std::int64_t>(map.update_period_s * 1e9);
    model.start(input->now_ns());
    std::int64_t next_tick = input->now_ns() + period_ns;
    bool more = true;
    while (!g_stop && more) {
      const double wait_wall_ns = static_cast<double>(next_tick - input->now_ns()) / input->rate();
      // Rounded up: a 0 ms wait while the tick is still ahead would spin.
      const auto wait = std::chrono::milliseconds(std::clamp<std::int64_t>(static_cast<std::int64_t>(std::ceil(wait_wall_ns / 1e6)), 1, 100));
      more = input->poll(sink, wait);
      const std::int64_t t = input->now_ns();
      if (t >= next_tick || !more) {
        model.update(t);
        publish();
        next_tick = std::max(next_tick + period_ns, t);  // no catch-up burst after a stall
      }
      pub.poll(std::chrono::milliseconds(0));  // never waits for a view
      if (trace.on()) {
        const auto ls = pub.stats();
        if (ls.bytes_sent != traced_bytes) trace.sent(traced_bytes = ls.bytes_sent, ls.deltas_sent);
      }
      if (!more && !o.exit_at_end) {
        // Log ended: keep serving the final state until told to stop.
        while (!g_stop) pub.poll(std::chrono::milliseconds(100));
      }
    }
    model.persist_now();
    trace.flush();
    if (o.verbose) {
      for (const auto& x : model.outputs())
        err << "  final " << protocol::find_signal(x.id)->name << " = " << fmt_double(x.value) << " ("
            << protocol::to_string(x.status) << ")\n";
    }
    if (!g_stop && o.linger_s > 0) {
      const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(o.linger_s);
      while (!g_stop && std::chrono::steady_clock::now() < until) pub.poll(std::chrono::milliseconds(20));
    }
    const auto& st = model.stats();
    auto ls = pub.stats();
    out << "meter-controller: " << st.frames << " frames (" << st.frames_mapped << " mapped, " << st.frames_unknown
        << " unknown id, " << st.error_frames << " error frames), " << st.values << " register values, "
        << ls.deltas_sent << " deltas / " << ls.snapshots_sent << " snapshots sent, odometer "
        << fmt_double(model.odometer().total_km()) << " km\n";
    return 0;
  } catch (const std::exception& e) {
    err << "meter-controller: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace meter::controller
