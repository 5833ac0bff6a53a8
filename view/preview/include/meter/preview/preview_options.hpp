// What meter-preview was asked to do, as plain data (the CLI fills it; defaults are the CLI's).
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace meter::preview {

struct PreviewOptions {
  std::string gltf;     // the artist's export (.glb / .gltf)
  std::string config;   // its scene config
  std::string catalog;  // signal catalog (VSS JSON); empty = the built-in one
  int msaa = 4;
  int panel_width = 380;  // the controls panel beside the scene

  // Values: the controls, plus any of these.
  std::vector<std::string> sets;  // NAME=VALUE[@status] applied at start (as meter-view --set)
  std::string values_csv;         // played from the start on the preview's clock
  std::string link;               // follow a controller: unix:/path | tcp:host:port | default
  int link_timeout_ms = 300;
  std::string key_file;        // the link's key file; empty = none
  bool insecure_link = false;  // allow TCP without a key file (a lab)
  bool link_lost = false;         // start with the link-loss (failsafe) look

  // Scripted runs (tests): the scene area of the last frame as a PNG, read from the window's
  // framebuffer; stop after N frames, or once the values CSV has played to its end.
  std::string screenshot;
  int exit_after_frames = 0;      // 0 = until the window is closed (or SIGINT/SIGTERM)
  bool exit_after_playback = false;
  double fps = 30.0;              // window frames per second (the scene redraws only on change)
};

// Runs the preview until closed; returns the process exit code. Errors that stop it before the
// first scene is on screen (no display, a first conversion that fails) go to `log` and return 1;
// later bad saves are shown in the window and the last good scene stays.
int run_preview(const PreviewOptions& options, std::ostream& log);

}  // namespace meter::preview
