// What every mode renders with: the scene package, the GL backend (offscreen, or a display's:
// --output), the renderer, the engine's frame pipeline (which owns the binding evaluator), the
// governor, the output directory, the timing CSV and the display's sink, set up from the options in
// that order.
#pragma once

#include <chrono>
#include <filesystem>
#include <memory>
#include <ostream>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/gl/program_binary_cache.hpp"
#include "meter/engine/pipeline/frame_pipeline.hpp"
#include "meter/engine/package_reader.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/backend.hpp"
#include "meter/platform/display.hpp"
#include "meter/runner/governed_frame.hpp"
#include "meter/runner/timing_csv.hpp"
#include "meter/runner/view_options.hpp"

namespace meter::runner {

class DisplaySink;

struct RenderContext {
  // Throws (ViewError, engine or platform errors) with a message naming what failed. With
  // options.info, prints the GL renderer line and scene statistics to `log`.
  RenderContext(const ViewOptions& options, std::ostream& log);
  ~RenderContext();

  std::chrono::steady_clock::time_point started;  // before the package was read
  // The start-up's steps end: the package read, the backend (a display: connected, EGL up) opened,
  // the renderer made (targets, programs, uploads, text); --info prints the split.
  std::chrono::steady_clock::time_point package_read{}, backend_opened{}, renderer_made{};
  std::filesystem::path out_dir;
  engine::Scene scene;
  std::unique_ptr<platform::GpuBackend> backend;
  platform::DisplayBackend* display = nullptr;  // the backend, when --output names a display
  // The linked programs kept across runs (--program-cache), null when off; outlives the renderer.
  std::unique_ptr<engine::ProgramBinaryCache> program_binaries;
  engine::Renderer renderer;
  // The engine's frame pipeline over the renderer, with the binding evaluator it owns; each mode
  // adds its sinks (and, live and play, the governor) and runs it.
  engine::FramePipeline pipeline;
  GovernedFrames governed;  // the frame pipeline's quality input in the live and play modes
  TimingCsv timing;         // a sink of every mode's frame pipeline
  // With a display: the sink that shows each frame (added by every mode: last in play and offline,
  // right after the integrity monitor in live), else nullptr.
  std::unique_ptr<DisplaySink> display_sink;
};

}  // namespace meter::runner
