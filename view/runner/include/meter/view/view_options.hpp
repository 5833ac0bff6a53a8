// What meter-view was asked to do, as plain data (the CLI fills it; defaults are the CLI's).
#pragma once

#include <string>
#include <vector>

namespace meter::view {

struct ViewOptions {
  std::string scene_path;        // .msp written by meter-convert
  std::string backend = "egl";   // egl | osmesa
  std::string size;              // WxH; empty = the scene config's size
  int msaa = 4;
  std::string out_dir = ".";
  std::string timing_csv;        // empty = none
  bool info = false;             // GL renderer line and scene statistics to the log

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
  std::string trace_csv;          // empty = none
  std::string trace_json;         // Chrome trace-event JSON (docs/tracing.md); empty = none
};

}  // namespace meter::view
