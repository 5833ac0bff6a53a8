// The preview's side panel (Dear ImGui): what is on screen and how it got there (scene generation,
// conversion and reload times, the converter's error after a bad save), the frame time, the
// values source (controls, a playing values CSV or the controller link) and one control per bound
// signal. Call between UiLayer::begin_frame() and end_frame().
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "meter/preview/signal_controls.hpp"
#include "meter/protocol/signal_table.hpp"

namespace meter::preview {

struct PanelStatus {
  std::string files;             // "cluster.glb + cluster.scene.json"
  std::uint64_t generation = 0;  // scenes converted and shown so far
  double convert_ms = 0.0;       // the shown scene's conversion
  double reload_ms = 0.0;        // first save event -> the new scene presented (0 = initial load)
  std::string error;             // the last save's error; empty when it converted
  double frame_ms = 0.0;         // whole window frame (events, engine, UI, swap)
  double render_ms = 0.0;        // the engine's part (update, submit, GPU)
  enum class Source { Controls, Playback, Link } source = Source::Controls;
  double play_t = 0.0, play_duration = 0.0;
  bool link_up = false;
  std::string link;              // the endpoint followed
};

struct PanelInput {
  bool link_lost = false;        // controls: draw the link-loss (failsafe) look
  bool restart_playback = false; // set by the panel's button, cleared by the caller
};

// Draws the panel in the box (x, 0, width, height) of the window. With Source::Controls the
// controls write into `values` (as Valid, or with the status the artist picks); otherwise they
// show the values read-only. Returns true when a value changed.
bool draw_controls_panel(int x, int width, int height, const PanelStatus& status,
                         const std::vector<SignalControl>& controls, protocol::SignalTable& values, PanelInput& input);

}  // namespace meter::preview
