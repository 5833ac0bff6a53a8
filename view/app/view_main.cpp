// meter-view: the graphics-MCU process. Renders a scene package offscreen (EGL or OSMesa).
//
//   offline:  meter-view --scene S.msp --set Vehicle.Speed=100 [--values v.csv --at 12.5s] --out DIR
//             renders that one state to DIR/frame.png and exits;
//   live:     meter-view --scene S.msp --link unix:/run/meter.sock --fps 30 --dump-every 30 --out DIR
//             renders at its own rate, decoupled from message arrival, dumping PNGs + frames.csv:
//             every Nth frame, the first frame at or after each --dump-at time, and the next frame
//             after each SIGUSR1 (on request: kill -USR1 <pid>).
#include <algorithm>
#include <csignal>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <thread>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <time.h>

#include <CLI/CLI.hpp>

#include "meter/engine/bindings.hpp"
#include "meter/engine/package.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/backend.hpp"
#include "meter/platform/image.hpp"
#include "meter/protocol/catalog.hpp"
#include "meter/protocol/link.hpp"

namespace {

using namespace meter;
using Clock = std::chrono::steady_clock;
volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }
volatile std::sig_atomic_t g_dump_request = 0;
void on_dump_request(int) { g_dump_request = 1; }

struct Failure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// "12.5s", "12.5", "250ms" -> seconds; `option` names the flag in errors.
double parse_time(const std::string& text, const std::string& option) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    throw Failure(option + ": \"" + text + "\" is not a time (examples: 12.5s, 250ms)");
  }
  const std::string unit = text.substr(used);
  if (unit == "ms") v /= 1000.0;
  else if (!unit.empty() && unit != "s") throw Failure(option + ": unknown unit \"" + unit + "\" (use s or ms)");
  if (!std::isfinite(v) || v < 0) throw Failure(option + ": time must be finite and >= 0");
  return v;
}

const protocol::SignalInfo& signal_named(const std::string& name, const std::string& where) {
  const auto* info = protocol::find_signal(name);
  if (!info) throw Failure(where + ": \"" + name + "\" is not in the signal catalog");
  return *info;
}

// NAME=VALUE (VALUE a number, or any text for Text signals), optionally NAME=VALUE@status.
void parse_set(const std::string& arg, std::map<int, engine::SignalValue>& values, const std::string& where) {
  auto eq = arg.find('=');
  if (eq == std::string::npos || eq == 0) throw Failure(where + ": expected NAME=VALUE, got \"" + arg + "\"");
  const auto& info = signal_named(arg.substr(0, eq), where);
  std::string value = arg.substr(eq + 1);
  engine::SignalValue sv;
  sv.status = protocol::SignalStatus::Valid;
  auto at = value.rfind('@');
  if (at != std::string::npos) {
    auto st = protocol::status_from_string(value.substr(at + 1));
    if (!st) throw Failure(where + ": unknown status \"" + value.substr(at + 1) + "\" (valid, timed_out, invalid, not_available)");
    sv.status = *st;
    value = value.substr(0, at);
  }
  if (info.kind == protocol::SignalKind::Text) {
    sv.text = value;
  } else {
    std::size_t used = 0;
    try {
      sv.value = std::stod(value, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != value.size() || !std::isfinite(sv.value)) {
      throw Failure(where + ": value \"" + value + "\" for " + std::string(info.name) + " is not a finite number");
    }
  }
  values[info.id] = sv;
}

// CSV rows "time,signal,value[,status]" (a header row is allowed); the state at `t` is, per signal,
// the last row with time <= t.
void load_values_csv(const std::string& path, double t, std::map<int, engine::SignalValue>& values) {
  std::ifstream in(path);
  if (!in) throw Failure(path + ": cannot open values CSV");
  std::string line;
  int lineno = 0;
  std::map<int, double> row_time;
  while (std::getline(in, line)) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> f;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) f.push_back(cell);
    const std::string where = path + ":" + std::to_string(lineno);
    double rt = 0;
    std::size_t used = 0;
    try {
      rt = std::stod(f.empty() ? "" : f[0], &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0) {
      if (lineno == 1) continue;  // header
      throw Failure(where + ": first column must be a time in seconds");
    }
    if (f.size() < 3 || f.size() > 4) throw Failure(where + ": expected time,signal,value[,status]");
    if (rt > t) continue;
    std::string set = f[1] + "=" + f[2] + (f.size() == 4 ? "@" + f[3] : "");
    std::map<int, engine::SignalValue> one;
    parse_set(set, one, where);
    for (auto& [id, v] : one) {
      if (!row_time.count(id) || row_time[id] <= rt) {
        row_time[id] = rt;
        values[id] = v;
      }
    }
  }
}

std::pair<int, int> parse_size(const std::string& s) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(s.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w < 16 || h < 16 || w > 8192 || h > 8192) {
    throw Failure("--size: expected WxH with 16..8192 each, got \"" + s + "\"");
  }
  return {w, h};
}

// frames.csv: one line per dumped PNG with the bound signals as drawn.
class FramesCsv {
 public:
  FramesCsv(const std::filesystem::path& file, const engine::BindingEvaluator& ev) : ev_(ev), out_(file) {
    if (!out_) throw Failure(file.string() + ": cannot write");
    out_ << "frame,time_s,png,link_up,drawn";
    for (std::size_t i = 0; i < ev.bindings().size(); ++i) {
      const auto& b = ev.bindings()[i];
      if (seen_.insert(b.signal).second) {
        columns_.push_back(i);
        out_ << "," << b.signal << "," << b.signal << ".status," << b.signal << ".failsafe";
      }
    }
    // A needle draws its smoothed value while a readout of the same signal draws the latest one,
    // so the signal's column alone cannot say what the readout showed: each text binding gets its
    // own column with the exact text drawn.
    for (std::size_t i = 0; i < ev.bindings().size(); ++i) {
      const auto& b = ev.bindings()[i];
      if (b.kind == engine::BindingKind::Text) {
        text_columns_.push_back(i);
        out_ << "," << b.node << ".text";
      }
    }
    out_ << "\n";
  }
  void row(std::uint64_t frame, double t, const std::string& png, bool link_up, bool drawn) {
    out_ << frame << "," << std::fixed << std::setprecision(4) << t << "," << png << "," << link_up << "," << drawn;
    for (std::size_t i : columns_) {
      const auto& s = ev_.states()[i];
      out_ << "," << std::setprecision(6) << s.value << "," << protocol::to_string(s.status) << "," << s.failsafe;
    }
    for (std::size_t i : text_columns_) out_ << "," << csv_quoted(ev_.states()[i].text);
    out_ << "\n";
    out_.flush();
  }

 private:
  const engine::BindingEvaluator& ev_;
  std::ofstream out_;
  std::set<std::string> seen_;
  std::vector<std::size_t> columns_;
  std::vector<std::size_t> text_columns_;

  // RFC 4180: texts may hold commas or quotes (a map entry, a designer's format string).
  static std::string csv_quoted(const std::string& text) {
    std::string q = "\"";
    for (char c : text) {
      if (c == '"') q += '"';
      q += c;
    }
    return q + "\"";
  }
};

// --trace: when link updates were applied and when each frame was rendered and written, on
// CLOCK_REALTIME (the clock of the controller's trace and of SocketCAN's kernel timestamps), so
// bench/latency can split a CAN frame's way to the PNG by stage. Rows:
//   a,<t_ns>,<sender monotonic ns>,<sequence>      a poll applied changes (newest frame's stamp)
//   r,<t_ns update>,<frame>,<t_ns rendered>          frame drawn and read back
//   w,<t_ns>,<frame>                                 its PNG written (writer thread)
class Trace {
 public:
  // Rows come from the render loop and from the PNG writer thread.
  explicit Trace(const std::string& path) {
    if (path.empty()) return;
    out_.open(path);
    if (!out_) throw Failure(path + ": cannot write the trace");
    out_ << "event,t_ns,a,b,c\n";
  }
  static std::int64_t now() {
    timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return static_cast<std::int64_t>(ts.tv_sec) * 1000000000LL + ts.tv_nsec;
  }
  void applied(std::int64_t sender_ns, std::uint64_t seq) {
    if (!out_.is_open()) return;
    std::lock_guard lock(mutex_);
    out_ << "a," << now() << "," << sender_ns << "," << seq << "\n";
  }
  void frame(std::uint64_t n, std::int64_t t_update, std::int64_t t_rendered) {
    if (!out_.is_open()) return;
    std::lock_guard lock(mutex_);
    out_ << "r," << t_update << "," << n << "," << t_rendered << "\n";
  }
  void png_written(std::uint64_t n) {
    if (!out_.is_open()) return;
    std::lock_guard lock(mutex_);
    out_ << "w," << now() << "," << n << "\n";
  }

 private:
  std::mutex mutex_;
  std::ofstream out_;
};

// Writes dumped frames as PNG on its own thread. Encoding one 640x240 PNG took 80-190 ms on the
// loaded CI host (measured with --trace), longer than a frame at 10 fps: done on the render
// thread it kept the link unserviced for that long every frame (no heartbeats, so the controller
// declared the view lost, and updates waited in the socket) and made the view miss its frame
// clock. At most kMaxPending images wait; a caller that finds the queue full waits (every dumped
// frame is written), servicing whatever `while_full` does meanwhile.
class PngWriter {
 public:
  static constexpr std::size_t kMaxPending = 3;
  explicit PngWriter(Trace& trace) : trace_(trace), thread_([this] { run(); }) {}
  ~PngWriter() { finish(); }
  PngWriter(const PngWriter&) = delete;
  PngWriter& operator=(const PngWriter&) = delete;

  template <typename WhileFull>
  void write(const platform::Image& image, std::filesystem::path file, std::uint64_t frame, WhileFull&& while_full) {
    for (;;) {
      {
        std::lock_guard lock(mutex_);
        rethrow();
        if (queue_.size() < kMaxPending) {
          queue_.push_back(Job{image, std::move(file), frame});
          break;
        }
      }
      while_full();
    }
    wake_.notify_one();
  }
  // Writes what is queued and stops the thread; throws the first write error, if any.
  void finish() {
    {
      std::lock_guard lock(mutex_);
      if (done_) return;
      done_ = true;
    }
    wake_.notify_one();
    thread_.join();
  }
  void check() {
    std::lock_guard lock(mutex_);
    rethrow();
  }

 private:
  struct Job {
    platform::Image image;
    std::filesystem::path file;
    std::uint64_t frame;
  };
  void rethrow() {
    if (!error_.empty()) throw Failure(error_);
  }
  void run() {
    for (;;) {
      Job job;
      {
        std::unique_lock lock(mutex_);
        wake_.wait(lock, [&] { return done_ || !queue_.empty(); });
        if (queue_.empty()) return;
        job = std::move(queue_.front());
      }
      try {
        platform::write_png(job.image, job.file);
        trace_.png_written(job.frame);
      } catch (const std::exception& e) {
        std::lock_guard lock(mutex_);
        if (error_.empty()) error_ = e.what();
      }
      std::lock_guard lock(mutex_);
      queue_.pop_front();  // only now: the queue bound counts the image being written
    }
  }
  Trace& trace_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Job> queue_;
  bool done_ = false;
  std::string error_;
  std::thread thread_;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"meter-view: instrument-cluster view (graphics MCU). Renders a scene package offscreen with EGL or OSMesa.\n"
               "Offline: --set/--values/--at render one state to <out>/frame.png. Live: --link ENDPOINT renders at --fps."};
  std::string scene_path, backend_name = "egl", size_text, out_dir = ".", link, values_csv, at_text, timing_csv, png_name = "frame.png";
  std::string trace_csv;
  std::vector<std::string> sets, dump_at_text;
  int msaa = 4, dump_every = 0, link_timeout_ms = 300;
  double fps = 30.0, duration = 0.0;
  bool dump_last = false, link_lost = false, info = false;
  app.add_option("--scene", scene_path, "scene package written by meter-convert (.msp)")->required();
  app.add_option("--backend", backend_name, "egl (Mesa surfaceless / EGL device, GLES 3) or osmesa (software)")
      ->check(CLI::IsMember({"egl", "osmesa"}))->capture_default_str();
  app.add_option("--size", size_text, "render size WxH (default: the scene config's size)");
  app.add_option("--msaa", msaa, "MSAA samples: 1, 2, 4 or 8")->check(CLI::IsMember({1, 2, 4, 8}))->capture_default_str();
  app.add_option("--out", out_dir, "output directory for PNGs, frames.csv")->capture_default_str();
  auto* set_opt = app.add_option("--set", sets, "offline: signal value NAME=VALUE[@status] (repeatable)");
  auto* values_opt = app.add_option("--values", values_csv, "offline: CSV of time,signal,value[,status] rows")->check(CLI::ExistingFile);
  app.add_option("--at", at_text, "offline: time in --values to render (12.5s, 250ms)")->needs(values_opt);
  app.add_option("--png", png_name, "offline: file name of the PNG inside --out")->capture_default_str();
  app.add_flag("--link-lost", link_lost, "offline: render the link-loss (failsafe) look");
  auto* link_opt = app.add_option("--link", link, "live: controller endpoint unix:/path | tcp:host:port | default");
  link_opt->excludes(set_opt)->excludes(values_opt);
  app.add_option("--fps", fps, "live: render rate")->check(CLI::Range(1.0, 240.0))->capture_default_str();
  app.add_option("--dump-every", dump_every, "live: write every Nth frame as PNG (0 = none)")->check(CLI::NonNegativeNumber);
  app.add_option("--duration", duration, "live: stop after SEC seconds (0 = until SIGINT/SIGTERM)")->check(CLI::NonNegativeNumber);
  app.add_flag("--dump-last", dump_last, "live: write the final frame on exit");
  app.add_option("--dump-at", dump_at_text,
                 "live: write the first frame at or after each time on the view's clock (frames.csv time_s), "
                 "e.g. --dump-at 2.5s,10s (repeatable); SIGUSR1 writes the next frame")
      ->delimiter(',')
      ->needs(link_opt);
  app.add_option("--timing-csv", timing_csv, "per-frame timing by stage (update, submit, GPU+readback) to this CSV");
  app.add_option("--link-timeout", link_timeout_ms,
                 "live: milliseconds of silence after which the link counts as lost (heartbeats every third of "
                 "it; the longer of the two sides' settings applies)")
      ->check(CLI::Range(30, 60000))->capture_default_str();
  app.add_option("--trace", trace_csv,
                 "live: latency trace CSV (link updates applied, frame rendered, PNG written; CLOCK_REALTIME ns)");
  app.add_flag("--info", info, "print the GL renderer line and scene statistics to stderr");
  CLI11_PARSE(app, argc, argv);
  // Before the slow start-up (package, GL context): a dump request must never hit SIGUSR1's
  // default action, which would end the process.
  std::signal(SIGUSR1, on_dump_request);

  try {
    namespace fs = std::filesystem;
    const auto process_start = Clock::now();
    engine::Scene scene = engine::read_package(scene_path);
    auto kind = platform::parse_backend_kind(backend_name);
    auto backend = platform::create_backend(*kind);
    engine::RendererOptions ro;
    ro.msaa = msaa;
    if (!size_text.empty()) std::tie(ro.width, ro.height) = parse_size(size_text);
    engine::Renderer renderer(*backend, scene, ro);
    engine::BindingEvaluator evaluator(scene);
    if (info) std::cerr << "meter-view: " << renderer.backend_info() << "; " << scene.draws.size() << " draws, " << scene.programs.size() << " programs\n";
    std::error_code ec;
    fs::create_directories(out_dir, ec);
    if (ec) throw Failure(out_dir + ": cannot create output directory: " + ec.message());
    std::ofstream timing;
    if (!timing_csv.empty()) {
      timing.open(timing_csv);
      if (!timing) throw Failure(timing_csv + ": cannot write");
      timing << "frame,time_s,update_ms,submit_ms,gpu_readback_ms,drawn\n";
    }
    auto log_timing = [&](std::uint64_t frame, double t, const engine::FrameTiming& ft) {
      if (timing.is_open()) {
        timing << frame << "," << std::fixed << std::setprecision(4) << t << "," << ft.update_ms << "," << ft.submit_ms << ","
               << ft.gpu_readback_ms << "," << ft.drawn << "\n";
      }
    };

    if (link.empty()) {
      // Offline: one state, straight to PNG.
      std::map<int, engine::SignalValue> values;
      if (!values_csv.empty()) load_values_csv(values_csv, at_text.empty() ? 1e300 : parse_time(at_text, "--at"), values);
      for (const auto& s : sets) parse_set(s, values, "--set");
      auto lookup = [&](int id) -> const engine::SignalValue* {
        auto it = values.find(id);
        return it == values.end() ? nullptr : &it->second;
      };
      evaluator.update(lookup, !link_lost, -1.0);  // negative dt: no smoothing, the state itself
      renderer.apply(evaluator.outputs());
      auto ft = renderer.render(true, true);
      log_timing(0, 0.0, ft);
      const fs::path png = fs::path(out_dir) / png_name;
      platform::write_png(renderer.last_image(), png);
      FramesCsv csv(fs::path(out_dir) / "frames.csv", evaluator);
      csv.row(0, 0.0, png.filename().string(), !link_lost, true);
      if (info) {
        std::cerr << "meter-view: wrote " << png.string() << " in "
                  << std::chrono::duration<double, std::milli>(Clock::now() - process_start).count() << " ms\n";
      }
      return 0;
    }

    // Live.
    std::vector<double> dump_at;
    for (const auto& text : dump_at_text) dump_at.push_back(parse_time(text, "--dump-at"));
    std::sort(dump_at.begin(), dump_at.end());
    std::size_t next_dump_at = 0;
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    protocol::LinkOptions lo;
    lo.name = "meter-view";
    lo.missed_heartbeats_for_loss = 3;
    lo.heartbeat_period = std::chrono::milliseconds(std::max(10, link_timeout_ms / lo.missed_heartbeats_for_loss));
    protocol::Subscriber sub(link == "default" ? protocol::default_endpoint() : protocol::Endpoint::parse(link), lo);
    FramesCsv csv(fs::path(out_dir) / "frames.csv", evaluator);
    std::map<int, engine::SignalValue> cache;
    auto lookup = [&](int id) -> const engine::SignalValue* {
      const auto& s = sub.get(static_cast<protocol::SignalId>(id));
      auto& v = cache[id];
      v.value = s.value;
      v.status = s.status;
      v.text = s.text;
      return &v;
    };
    Trace trace(trace_csv);
    auto trace_applied = [&] { trace.applied(sub.last_sender_time_ns(), sub.last_sequence_applied()); };
    // Every pending message, not one batch: a view that renders slower than the link delivers
    // must coalesce the backlog to the latest state each frame instead of drawing it frame by
    // frame seconds late. Bounded (a flooding peer cannot hold the frame back forever); each round
    // reads up to 64 socket buffers.
    auto drain = [&] {
      for (int round = 0; round < 16; ++round) {
        if (!sub.poll(std::chrono::milliseconds(0))) break;
        trace_applied();
      }
    };
    const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / fps));
    const auto start = Clock::now();
    auto next = start;
    auto last = start;
    std::uint64_t frame = 0;
    PngWriter png_writer(trace);
    auto dump = [&](std::uint64_t n, double t, bool drawn) {
      char name[32];
      std::snprintf(name, sizeof name, "frame_%06llu.png", static_cast<unsigned long long>(n));
      // The row is the state this image was rendered with; the file follows from the writer.
      csv.row(n, t, name, sub.link_up(), drawn);
      png_writer.write(renderer.last_image(), fs::path(out_dir) / name, n, [&] {
        if (sub.poll(std::chrono::milliseconds(5))) trace_applied();
      });
    };
    while (!g_stop) {
      const auto now0 = Clock::now();
      if (duration > 0 && now0 - start >= std::chrono::duration<double>(duration)) break;
      // Messages are consumed whenever they arrive; frames happen on the render clock only.
      drain();
      while (!g_stop) {
        const auto now = Clock::now();
        if (now >= next) break;
        if (sub.poll(std::chrono::duration_cast<std::chrono::milliseconds>(next - now))) trace_applied();
        if (Clock::now() < next && next - Clock::now() < std::chrono::milliseconds(1)) std::this_thread::sleep_until(next);
      }
      // Whatever arrived while waiting (or while the last frame rendered) is applied before the
      // frame: the frame always draws the newest state, and an EOF is seen now, not a frame later.
      drain();
      const auto now = Clock::now();
      const double dt = std::chrono::duration<double>(now - last).count();
      last = now;
      const double t = std::chrono::duration<double>(now - start).count();
      const std::int64_t t_update = trace.now();
      evaluator.update(lookup, sub.link_up(), dt);
      renderer.apply(evaluator.outputs());
      bool want = dump_every > 0 && frame % static_cast<std::uint64_t>(dump_every) == 0;
      // Times that fell due since the last frame: one dump covers them all.
      for (; next_dump_at < dump_at.size() && dump_at[next_dump_at] <= t; ++next_dump_at) want = true;
      if (g_dump_request) {
        g_dump_request = 0;
        want = true;
      }
      auto ft = renderer.render(false, want);
      const std::int64_t t_rendered = trace.now();
      log_timing(frame, t, ft);
      trace.frame(frame, t_update, t_rendered);
      if (want) dump(frame, t, ft.drawn);
      sub.send_status(renderer.stats().drawn, 0);
      ++frame;
      next += period;
      if (next < Clock::now()) next = Clock::now();  // late: do not burst to catch up
    }
    if (dump_last && frame > 0) {
      renderer.read();
      dump(frame - 1, std::chrono::duration<double>(Clock::now() - start).count(), false);
    }
    png_writer.finish();  // every dumped frame is on disk before the exit status says so
    png_writer.check();
    const auto& st = renderer.stats();
    std::cerr << "meter-view: " << st.frames << " frames, " << st.drawn << " drawn, " << st.skipped << " skipped (inputs unchanged)\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "meter-view: error: " << e.what() << "\n";
    return 1;
  }
}
