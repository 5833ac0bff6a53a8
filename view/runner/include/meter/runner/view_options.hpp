// What meter-view was asked to do, as plain data (the CLI fills it; defaults are the CLI's).
#pragma once

#include <string>
#include <vector>

namespace meter::runner {

struct ViewOptions {
  std::string scene_path;        // .msp written by meter-convert
  std::string backend = "egl";   // egl | osmesa
  // Where frames go besides the PNG dump: offscreen (none), wayland[:SOCKET] (docs/display.md).
  std::string output = "offscreen";
  // Live with a display: late (at the last safe moment before the display's next latch; the
  // default: on a quiet machine it showed changes 7-12 ms sooner at p99 with no refresh missed) or
  // callback (a due frame drawn as soon as the display took the frame before); display_latch.hpp.
  std::string latch = "late";
  // --output drm: auto | atomic | legacy (platform::DisplayOptions::drm_modeset).
  std::string drm_modeset = "auto";
  // play with --output: after the recording, the last frame stays shown until SIGINT/SIGTERM.
  bool hold = false;
  std::string size;              // WxH; empty = the scene config's size
  int msaa = 4;
  std::string out_dir = ".";
  std::string timing_csv;        // empty = none
  bool info = false;             // GL renderer line and scene statistics to the log
  // Where linked programs are kept across runs (engine::ProgramBinaryCache): empty = the default,
  // $XDG_CACHE_HOME/meter or ~/.cache/meter; "off" = every program compiled at every start.
  std::string program_cache;

  // offline (link empty)
  std::vector<std::string> sets;  // NAME=VALUE[@status]
  std::string values_csv;
  std::string at;                 // time in values_csv; empty = its end
  std::string png_name = "frame.png";
  bool link_lost = false;

  // live
  std::string link;               // unix:/path | tcp:host:port | default
  double fps = 30.0;
  int dump_every = 0;
  double duration_s = 0.0;        // 0 = until SIGINT/SIGTERM
  bool dump_last = false;
  std::vector<std::string> dump_at;  // times, e.g. "2.5s"
  int link_timeout_ms = 300;
  std::string key_file;           // the link's key file (MAC on every frame); empty = none
  bool insecure_link = false;     // allow TCP without a key file (a lab)
  std::string trace_csv;          // empty = none

  // play: a link recording rendered on its own simulated clock (play_recording.hpp); uses fps,
  // dump_every, dump_at, dump_last and duration_s (seconds of recording; 0 = all of it)
  std::string play;

  // The signal catalog (VSS JSON); empty = the built-in default. Live, a view without --catalog
  // (or with catalog_from_controller) takes its controller's catalog when it differs: it waits up
  // to catalog_wait_ms for the controller before loading the scene, so a scene binding a signal
  // only the controller's catalog has still loads.
  std::string catalog;
  bool catalog_from_controller = false;
  int catalog_wait_ms = 2000;
  std::string trace_json;         // Chrome trace-event JSON (docs/tracing.md); empty = none

  // The live pipeline (docs/pipeline.md). overlapped: concurrent, and a frame's GL work executes
  // (fenced) while the next frame is taken in, evaluated and planned. concurrent: PNG check/encode on the writer thread fed
  // through a bounded buffer, readback through pixel-pack buffers, latency-aware frame starts;
  // sequential: the loop as it was (synchronous readback, frames on the --fps ticks only).
  std::string pipeline = "overlapped";
  std::string dump_policy;        // drop | block; empty = drop when concurrent, block when sequential
  bool stats = false;             // print the stage shares and the bottleneck every stats_interval_s
  double stats_interval_s = 1.0;
  double trace_on_overrun_ms = 0.0;  // > 0: keep the last seconds of trace; write them when a frame takes longer
  // Display integrity (docs/integrity.md): the monitor runs when the package has safety regions;
  // inject_fault is the test-only fault (hidden --inject-fault KIND[:REGION]@FIRST[-LAST]).
  bool integrity_monitor = true;
  std::string inject_fault;
  std::string inject_slow_stage;  // test only: STAGE:MS slept in one live stage (hidden --inject-slow-stage)

  // The frame-rate governor (docs/uniform-frame-rate.md), live and play. target_ms > 0 turns it on
  // unless governor == "off"; quality fixes the quality instead ("full" or "cheapest", the
  // cheapest the cost file predicts); costs empty = <scene_path>.costs.json (meter-calibrate).
  // full_redraw: every drawn frame redrawn in full (partial redraw off). inject_cost is the
  // test-only busy time per drawn pixel (hidden --inject-cost NS_PER_PIXEL@FIRST-LAST).
  double target_ms = 0.0;
  std::string governor;           // on | off; empty = on when target_ms > 0
  std::string quality;            // full | cheapest; empty = the governor's choice (or full)
  std::string costs;
  bool full_redraw = false;
  std::string inject_cost;
};

}  // namespace meter::runner
