// meter-preview: the artist's preview window. Converts a glTF export + scene config in-process,
// shows the engine's frame (OpenGL ES 3 through EGL, as meter-view renders offscreen) and reloads
// within a second of either file being saved. A thin CLI11 front end over meter_preview
// (view/preview).
//
//   meter-preview scenes/cluster/cluster.glb -c scenes/cluster/cluster.scene.json
//   meter-preview S.glb -c S.scene.json --values drive.csv       plays the CSV
//   meter-preview S.glb -c S.scene.json --link default           follows a running controller
//   meter-preview S.glb -c S.scene.json --set Vehicle.Speed=100 --exit-after-frames 5 --screenshot shot.png
#include <malloc.h>

#include <iostream>

#include <CLI/CLI.hpp>

#include "meter/preview/preview_options.hpp"
#include "meter/protocol/link_options.hpp"

int main(int argc, char** argv) {
  using namespace meter::preview;
  CLI::App app{"meter-preview: the artist's preview window. Shows a glTF scene with its scene config as the "
               "engine draws it and reloads it when either file is saved."};
  PreviewOptions o;
  app.add_option("gltf", o.gltf, "glTF 2.0 scene (.glb or .gltf)")->required()->check(CLI::ExistingFile);
  app.add_option("-c,--config", o.config, "scene config JSON (meter-scene-config/1, docs/scene-config.md)")
      ->required()->check(CLI::ExistingFile);
  app.add_option("--catalog", o.catalog, "signal catalog (VSS JSON, docs/catalog.md); default: the built-in one")
      ->check(CLI::ExistingFile);
  app.add_option("--msaa", o.msaa, "MSAA samples: 1, 2, 4 or 8")->check(CLI::IsMember({1, 2, 4, 8}))->capture_default_str();
  auto* set_opt = app.add_option("--set", o.sets, "signal value NAME=VALUE[@status] at start (repeatable)");
  auto* values_opt = app.add_option("--values", o.values_csv, "play a CSV of time,signal,value[,status] rows (meter-view --values)")
      ->check(CLI::ExistingFile);
  auto* link_opt = app.add_option("--link", o.link, "follow a controller: unix:/path | tcp:host:port | default");
  link_opt->excludes(set_opt)->excludes(values_opt);
  app.add_option("--key-file", o.key_file, meter::protocol::kKeyFileHelp)->needs(link_opt);
  app.add_flag("--insecure-link", o.insecure_link, meter::protocol::kInsecureLinkHelp)->needs(link_opt);
  app.add_option("--link-timeout", o.link_timeout_ms, "milliseconds of silence after which the link counts as lost")
      ->check(CLI::Range(30, 60000))->capture_default_str();
  app.add_flag("--link-lost", o.link_lost, "start with the link-loss (failsafe) look");
  app.add_option("--screenshot", o.screenshot, "scripted: write the scene area of the last frame (read from the window) as PNG");
  app.add_option("--exit-after-frames", o.exit_after_frames, "scripted: stop after N window frames")->check(CLI::PositiveNumber);
  app.add_flag("--exit-after-playback", o.exit_after_playback, "scripted: stop once --values has played to its last row")
      ->needs(values_opt);
  app.add_option("--fps", o.fps, "window frames per second")->check(CLI::Range(1.0, 240.0))->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  // A reload frees the old scene's render targets (20 MB a target at 1280x480 MSAA 4) and the driver
  // allocates the new scene's: memory the process keeps is reused, where memory given back to the
  // kernel comes back a page fault per 4 KiB page (55 ms for one such target on the test machine
  // against 1 ms reused). So large blocks come from the heap and a freed heap top is kept.
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
  mallopt(M_TRIM_THRESHOLD, 512 << 20);
  return run_preview(o, std::cerr);
}
