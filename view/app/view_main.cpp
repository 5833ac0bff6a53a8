// meter-view: the graphics-MCU process. Renders a scene package offscreen (EGL or OSMesa), and shows
// it on a display with --output wayland.
// A thin CLI11 front end over meter_view_runner (view/runner).
//
//   offline:  meter-view --scene S.msp --set Vehicle.Speed=100 [--values v.csv --at 12.5s] --out DIR
//             renders that one state to DIR/frame.png and exits;
//   play:     meter-view --scene S.msp --play drive.rec --fps 10 --dump-every 10 --out DIR
//             renders a link recording on its own simulated clock (frame k at k/fps), no waiting;
//   live:     meter-view --scene S.msp --link unix:/run/meter.sock --fps 30 --dump-every 30 --out DIR
//             renders at its own rate, decoupled from message arrival, dumping PNGs + frames.csv:
//             every Nth frame, the first frame at or after each --dump-at time, and the next frame
//             after each SIGUSR1 (on request: kill -USR1 <pid>).
#include <iostream>

#include <CLI/CLI.hpp>

#include "meter/log_sinks/log_options.hpp"
#include "meter/log_sinks/open_log_sink.hpp"
#include "meter/protocol/link_options.hpp"
#include "meter/runner/run_view.hpp"

namespace {

// The live pipeline's options (docs/pipeline.md): how frames overlap, what a busy writer does, the
// bottleneck report and the overrun trace.
void add_pipeline_options(CLI::App& app, meter::runner::ViewOptions& o, CLI::Option* link_opt) {
  app.add_option("--pipeline", o.pipeline,
                 "live: overlapped (concurrent, and a frame's GL work executes, fenced, while the next frame "
                 "is taken in, evaluated and planned), concurrent (PNG check/encode on the writer thread "
                 "through a bounded buffer, readback through pixel-pack buffers, a frame as soon as a change "
                 "may be drawn; each frame waited for with glFinish) or sequential (the loop as before: frames "
                 "on the --fps ticks, synchronous readback); docs/pipeline.md")
      ->check(CLI::IsMember({"overlapped", "concurrent", "sequential"}))->capture_default_str()->needs(link_opt);
  app.add_option("--dump-policy", o.dump_policy,
                 "live: when the PNG writer is behind, drop the --dump-every frame (counted) or block the "
                 "render loop until it has room (default: drop when concurrent, block when sequential); "
                 "--dump-at and SIGUSR1 dumps always block")
      ->check(CLI::IsMember({"drop", "block"}))->needs(link_opt);
  app.add_flag("--stats", o.stats,
               "live: print every stage's busy / waiting-for-input / waiting-for-output shares and the "
               "bottleneck every --stats-interval seconds and at exit")
      ->needs(link_opt);
  app.add_option("--stats-interval", o.stats_interval_s, "live: seconds between --stats lines")
      ->check(CLI::Range(0.1, 3600.0))->capture_default_str();
  app.add_option("--trace-on-overrun", o.trace_on_overrun_ms,
                 "live: keep the last 5 s of trace events in memory and write them to <out>/overrun_<frame>.json "
                 "when a frame takes longer than MS milliseconds (at most one file per 5 s)")
      ->check(CLI::PositiveNumber)->needs(link_opt);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace meter::runner;
  CLI::App app{"meter-view: instrument-cluster view (graphics MCU). Renders a scene package offscreen with EGL or OSMesa.\n"
               "Offline: --set/--values/--at render one state to <out>/frame.png. Live: --link ENDPOINT renders at --fps."};
  ViewOptions o;
  app.add_option("--scene", o.scene_path, "scene package written by meter-convert (.msp)")->required();
  app.add_option("--backend", o.backend, "egl (Mesa surfaceless / EGL device, GLES 3) or osmesa (software)")
      ->check(CLI::IsMember({"egl", "osmesa"}))->capture_default_str();
  app.add_option("--output", o.output,
                 "where frames are shown: offscreen (none; the default), wayland (a toplevel on $WAYLAND_DISPLAY's "
                 "compositor, fullscreen), wayland:SOCKET, drm (KMS on /dev/dri/card0, no compositor) or "
                 "drm:/dev/dri/cardN; the PNG dump keeps working (docs/display.md)")
      ->capture_default_str();
  app.add_option("--latch", o.latch,
                 "live with --output: late (a due frame is drawn at the last safe moment before the display's "
                 "next latch, predicted from its frame callbacks or page flips and presentation feedback) or "
                 "callback (as soon as the display took the frame before); docs/display.md")
      ->check(CLI::IsMember({"late", "callback"}))->capture_default_str();
  app.add_option("--drm-modeset", o.drm_modeset,
                 "--output drm: auto (atomic modesetting where the driver offers it, else legacy), atomic (refused "
                 "without it) or legacy (drmModeSetCrtc + drmModePageFlip, as on a driver without atomic)")
      ->check(CLI::IsMember({"auto", "atomic", "legacy"}))->capture_default_str();
  app.add_flag("--hold", o.hold, "play with --output: after the recording, keep its last frame shown until SIGINT/SIGTERM");
  app.add_option("--size", o.size, "render size WxH (default: the scene config's size)");
  app.add_option("--msaa", o.msaa, "MSAA samples: 1, 2, 4 or 8")->check(CLI::IsMember({1, 2, 4, 8}))->capture_default_str();
  app.add_option("--out", o.out_dir, "output directory for PNGs, frames.csv")->capture_default_str();
  auto* set_opt = app.add_option("--set", o.sets, "offline: signal value NAME=VALUE[@status] (repeatable)");
  auto* values_opt = app.add_option("--values", o.values_csv, "offline: CSV of time,signal,value[,status] rows")->check(CLI::ExistingFile);
  app.add_option("--at", o.at, "offline: time in --values to render (12.5s, 250ms)")->needs(values_opt);
  app.add_option("--png", o.png_name, "offline: file name of the PNG inside --out")->capture_default_str();
  app.add_flag("--link-lost", o.link_lost, "offline: render the link-loss (failsafe) look");
  auto* link_opt = app.add_option("--link", o.link, "live: controller endpoint unix:/path | tcp:host:port | default");
  link_opt->excludes(set_opt)->excludes(values_opt);
  app.add_option("--key-file", o.key_file, std::string("live: ") + meter::protocol::kKeyFileHelp)->needs(link_opt);
  app.add_flag("--insecure-link", o.insecure_link, std::string("live: ") + meter::protocol::kInsecureLinkHelp)->needs(link_opt);
  app.add_option("--play", o.play,
                 "play: render this link recording (meter-controller run --record, meter-linkdump -o) on its own "
                 "simulated clock, frame k at k/--fps s, as fast as the machine allows")
      ->check(CLI::ExistingFile)->excludes(link_opt)->excludes(set_opt)->excludes(values_opt);
  app.add_option("--fps", o.fps, "live: render rate; play: frames per second of recording time")->check(CLI::Range(1.0, 240.0))->capture_default_str();
  app.add_option("--dump-every", o.dump_every, "live: write every Nth frame as PNG (0 = none)")->check(CLI::NonNegativeNumber);
  app.add_option("--duration", o.duration_s, "live: stop after SEC seconds (0 = until SIGINT/SIGTERM); play: SEC seconds of the recording (0 = all); offline with --output: how long the frame stays shown (0 = until SIGINT/SIGTERM)")->check(CLI::NonNegativeNumber);
  app.add_flag("--dump-last", o.dump_last, "live: write the final frame on exit");
  app.add_option("--dump-at", o.dump_at,
                 "live and play: write the first frame at or after each time on the view's clock (frames.csv time_s), "
                 "e.g. --dump-at 2.5s,10s (repeatable); SIGUSR1 writes the next frame")
      ->delimiter(',');
  app.add_option("--timing-csv", o.timing_csv, "per-frame timing by stage (update, submit, GPU+readback) to this CSV");
  app.add_option("--link-timeout", o.link_timeout_ms,
                 "live: milliseconds of silence after which the link counts as lost (heartbeats every third of "
                 "it; the longer of the two sides' settings applies)")
      ->check(CLI::Range(30, 60000))->capture_default_str();
  app.add_option("--trace", o.trace_csv,
                 "live: latency trace CSV (link updates applied, frame rendered, PNG written; CLOCK_REALTIME ns)");
  app.add_option("--catalog", o.catalog,
                 "signal catalog, a VSS JSON file (docs/catalog.md); default: the built-in "
                 "protocol/catalog/signals.vss.json. Live without it: the controller's catalog is used")
      ->check(CLI::ExistingFile);
  app.add_flag("--catalog-from-controller", o.catalog_from_controller,
               "live: use the controller's catalog when it differs from --catalog (instead of refusing the link)")
      ->needs(link_opt);
  app.add_option("--catalog-wait", o.catalog_wait_ms,
                 "live: milliseconds to wait for the controller (and its catalog) before loading the scene")
      ->check(CLI::Range(0, 60000))->capture_default_str();
  app.add_option("--trace-json", o.trace_json,
                 "live: Chrome trace-event JSON (intake, evaluate, render, readback, encode on CLOCK_MONOTONIC, "
                 "the controller's --trace-json clock; opens in Perfetto UI)");
  add_pipeline_options(app, o, link_opt);
  app.add_option("--program-cache", o.program_cache,
                 "directory where linked GL programs are kept across runs as the driver's binaries (default "
                 "$XDG_CACHE_HOME/meter, else ~/.cache/meter); off: compile every program at every start")
      ->capture_default_str();
  app.add_flag("--info", o.info, "print the GL renderer line and scene statistics to stderr");
  bool no_monitor = false;
  app.add_flag("--no-integrity-monitor", no_monitor,
               "live: do not check the package's safety regions after each frame (docs/integrity.md)");
  // Test-only (docs/integrity.md): hidden from --help, it draws a wrong display on purpose.
  app.add_option("--inject-fault", o.inject_fault, "")->group("")->needs(link_opt);
  // Test-only (docs/pipeline.md): hidden, STAGE:MS slept in one stage so --stats must name it.
  app.add_option("--inject-slow-stage", o.inject_slow_stage, "")->group("")->needs(link_opt);
  // The frame-rate governor (docs/uniform-frame-rate.md).
  app.add_option("--target-ms", o.target_ms,
                 "live and play: target frame time; turns the frame-rate governor on (each frame drawn with the best "
                 "quality the package's measured costs predict within it)")
      ->check(CLI::PositiveNumber);
  app.add_option("--governor", o.governor, "live and play: on (the default with --target-ms) or off")
      ->check(CLI::IsMember({"on", "off"}));
  app.add_option("--quality", o.quality,
                 "live and play: a fixed quality instead of the governor's: full, or cheapest (every unit at the level "
                 "and the global rung the cost file predicts cheapest)")
      ->check(CLI::IsMember({"full", "cheapest"}));
  app.add_option("--costs", o.costs, "the governor's cost file (meter-calibrate; default: SCENE.costs.json beside --scene)");
  app.add_flag("--full-redraw", o.full_redraw, "redraw every drawn frame in full (partial redraw off; benchmarks)");
  // Test-only (docs/uniform-frame-rate.md): hidden from --help, it makes frames slower on purpose.
  app.add_option("--inject-cost", o.inject_cost, "")->group("");
  meter::log_sinks::LogOptions log_options;  // every mode: offline, play, live
  meter::log_sinks::add_log_options(app, log_options);
  CLI11_PARSE(app, argc, argv);
  if (!o.dump_at.empty() && o.link.empty() && o.play.empty()) {
    std::cerr << "--dump-at requires --link or --play\n";
    return 2;
  }
  if ((o.target_ms > 0 || !o.governor.empty() || !o.quality.empty() || !o.inject_cost.empty()) && o.link.empty() &&
      o.play.empty()) {
    std::cerr << "--target-ms, --governor, --quality and --inject-cost require --link or --play\n";
    return 2;
  }
  o.integrity_monitor = !no_monitor;
  meter::log_sinks::ProcessLog log("meter-view", log_options.sink, log_options.level, "view");  // every log line a record
  return run_view(o, log.err());
}
