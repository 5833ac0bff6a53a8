// meter-preview's loop: window events, saves -> reload, values (controls, a playing CSV or the
// controller link) -> bindings -> the engine's frame -> the window, the side panel, swap.
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <ostream>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/pipeline/frame_pipeline.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/image.hpp"
#include "meter/platform/program_cache.hpp"
#include "meter/preview/controls_panel.hpp"
#include "meter/preview/file_watcher.hpp"
#include "meter/platform/frame_blit.hpp"
#include "meter/preview/preview_options.hpp"
#include "meter/preview/preview_window.hpp"
#include "meter/preview/scene_reloader.hpp"
#include "meter/preview/signal_controls.hpp"
#include "meter/preview/ui_layer.hpp"
#include "meter/preview/values_player.hpp"
#include "meter/protocol/catalog.hpp"
#include "meter/protocol/link.hpp"
#include "meter/runner/process_signals.hpp"
#include "meter/runner/values_input.hpp"

namespace meter::preview {
namespace {

using Clock = std::chrono::steady_clock;

double ms_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// The scene on screen with what draws it; the renderer and the pipeline refer to the scene. The
// preview is a policy over the engine's frame pipeline with no sink: the state from the controls,
// a playing values file or the link, a frame at every window event or tick; the window shows it.
struct ShownScene {
  ShownScene(std::shared_ptr<const engine::Scene> s, platform::GpuBackend& gpu, int msaa, platform::ProgramCache& programs)
      : scene(std::move(s)), renderer(gpu, *scene, renderer_options(msaa, programs)), pipeline(*scene, renderer) {}
  static engine::RendererOptions renderer_options(int msaa, platform::ProgramCache& programs) {
    engine::RendererOptions o;
    o.msaa = msaa;
    o.programs = &programs;  // a reload links only the programs whose sources changed
    return o;
  }
  std::shared_ptr<const engine::Scene> scene;
  engine::Renderer renderer;
  engine::FramePipeline pipeline;  // owns the binding evaluator
};

// The scene area 1:1 at the top left, the panel to its right; before any scene converted, the
// panel beside an empty 640x480 area.
WindowSize window_size_for(const engine::Scene* scene, int panel_width) {
  const int w = scene ? scene->config.size[0] : 640;
  const int h = scene ? scene->config.size[1] : 480;
  return {w + panel_width, std::max(h, 480)};
}

std::string file_names(const SceneFiles& f) {
  return std::filesystem::path(f.gltf).filename().string() + " + " + std::filesystem::path(f.config).filename().string();
}

class PreviewLoop {
 public:
  PreviewLoop(const PreviewOptions& options, std::ostream& log)
      : options_(options),
        log_(log),
        reloader_({options.gltf, options.config}),
        watcher_({options.gltf, options.config}) {
    for (const auto& s : options.sets) runner::parse_set(s, values_, "--set");
    if (!options.values_csv.empty()) player_.emplace(ValuesPlayer::load(options.values_csv));
    if (!options.link.empty()) {
      auto lo = protocol::link_options("meter-preview", std::chrono::milliseconds(options.link_timeout_ms));
      lo.key_file = options.key_file;
      lo.insecure_link = options.insecure_link;
      subscriber_.emplace(protocol::endpoint_from_option(options.link), lo);
    }
    input_.link_lost = options.link_lost;
    status_.files = file_names(reloader_.files());
    status_.link = options.link;
    status_.source = subscriber_ ? PanelStatus::Source::Link
                     : player_   ? PanelStatus::Source::Playback
                                 : PanelStatus::Source::Controls;
    status_.play_duration = player_ ? player_->duration() : 0.0;
  }

  int run() {
    const bool first_ok = reloader_.reload();
    if (!first_ok) {
      // The window opens anyway, with the error on its panel, and waits for a save that converts.
      status_.error = reloader_.error();
      log_ << "meter-preview: the scene does not convert (waiting for a save that does): " << status_.error << "\n";
    }
    window_ = create_glfw_window(window_size_for(reloader_.scene().get(), options_.panel_width),
                                 "meter-preview: " + status_.files);
    blit_ = std::make_unique<platform::FrameBlit>(window_->gpu().gl());
    programs_ = std::make_unique<platform::ProgramCache>(window_->gpu().gl());
    ui_ = std::make_unique<UiLayer>(*window_);
    if (first_ok) adopt(Clock::now());
    log_ << "meter-preview: " << window_->gpu().renderer_info() << "\n";
    play_began_ = Clock::now();
    auto last = Clock::now();
    std::uint64_t frame = 0;
    int exit_code = 0;
    // Scripted runs draw every window frame, so frame counts mean the same on every machine.
    const bool scripted = options_.exit_after_frames > 0 || options_.exit_after_playback;
    auto presented = Clock::now();
    int ui_frames = 0;  // window frames still to draw after an input event (UI hover, focus)
    while (!window_->close_requested() && !runner::stop_requested()) {
      // A pending save is converted as soon as it settled; otherwise wait for events at the frame rate.
      window_->poll_events(frame == 0 ? 0.0 : reloader_.pending() || reloader_.converting() ? 0.005 : 1.0 / options_.fps);
      const auto now = Clock::now();
      follow_saves(now);
      const double dt = std::chrono::duration<double>(now - last).count();
      last = now;
      update_values(now);
      const bool engine_drew = step_scene(dt);
      if (window_->take_activity()) ui_frames = 3;
      // An idle window is not drawn again (the engine skipped the frame, no event, nothing new to
      // show): the CPU stays free for the next reload. The panel's numbers refresh once a second.
      const bool playing = player_ && status_.play_t <= player_->duration();
      if (!(scripted || engine_drew || ui_frames > 0 || ui_changed_ || awaiting_screen_ || playing ||
            now - presented >= std::chrono::seconds(1)))
        continue;
      ui_frames = std::max(0, ui_frames - 1);
      ui_changed_ = false;
      // A scripted run ends on a frame that shows the whole scene area (a resize after a reload
      // takes effect a few events later).
      const bool whole = !shown_ || fits(window_->framebuffer_size());
      const bool last_frame = whole && options_.exit_after_frames > 0 &&
                              frame + 1 >= static_cast<std::uint64_t>(options_.exit_after_frames);
      const bool played = whole && options_.exit_after_playback && player_ && status_.play_t >= player_->duration();
      draw_window();
      if ((last_frame || played) && !options_.screenshot.empty()) exit_code = screenshot();
      window_->present();
      presented = Clock::now();
      if (awaiting_screen_) report_on_screen();
      status_.frame_ms = ms_between(now, presented);
      ++frame;
      if (last_frame || played) break;
    }
    shown_.reset();  // its GL objects go before the window's context
    programs_.reset();
    ui_.reset();
    blit_.reset();
    window_.reset();
    return exit_code;
  }

 private:
  // Saves seen by the watcher start a conversion (on a worker thread) once they settled; a scene
  // that converts replaces the one on screen, one that does not leaves it there with the error on
  // the panel. The window goes on drawing the old scene meanwhile.
  void follow_saves(Clock::time_point now) {
    if (!watcher_.poll().empty()) reloader_.changed(now);
    if (!reloader_.converting() && reloader_.due(now)) {
      reload_cpu_began_ = std::clock();
      reloader_.begin();  // nothing new on the panel until it finishes: no window frame for it
    }
    const auto done = reloader_.finish();
    if (!done) return;
    ui_changed_ = true;
    if (*done) {
      adopt(reloader_.converting_change());
    } else {
      status_.error = reloader_.error();
      log_ << "meter-preview: the save does not convert (still showing scene " << status_.generation << "): "
           << status_.error << "\n";
    }
  }

  // Puts the reloader's new scene on screen: the signal values and the panel's settings stay, the
  // evaluator and renderer are new. A scene the GL context cannot draw counts as a bad save.
  void adopt(Clock::time_point change) {
    const auto began = Clock::now();
    compiles_before_ = programs_->compiles();
    bool drawable = true;
    try {
      auto next = std::make_unique<ShownScene>(reloader_.scene(), window_->gpu(), options_.msaa, *programs_);
      build_ms_ = ms_between(began, Clock::now());
      const bool resized = !shown_ || next->renderer.width() != shown_->renderer.width() ||
                           next->renderer.height() != shown_->renderer.height();
      shown_ = std::move(next);
      if (resized) window_->resize(window_size_for(shown_->scene.get(), options_.panel_width));
    } catch (const std::exception& e) {
      drawable = false;
      status_.error = std::string("the scene converted but cannot be drawn: ") + e.what();
    }
    programs_->trim();  // the old scene's programs the new one does not use (or the failed one's)
    if (!drawable) {
      log_ << "meter-preview: " << status_.error << "\n";
      return;
    }
    controls_ = controls_for(shown_->scene->config.bindings, values_.catalog());
    status_.generation = reloader_.generation();
    status_.convert_ms = reloader_.last_convert_ms();
    status_.error.clear();
    save_time_ = change;
    awaiting_screen_ = true;
  }

  // The first swap showing a new scene: how long after the save it took.
  void report_on_screen() {
    awaiting_screen_ = false;
    status_.reload_ms = status_.generation > 1 ? ms_between(save_time_, Clock::now()) : 0.0;
    log_ << "meter-preview: scene " << status_.generation << " on screen";
    if (status_.generation > 1) log_ << " " << static_cast<long>(status_.reload_ms) << " ms after the save";
    log_ << " (conversion " << static_cast<long>(status_.convert_ms) << " ms, renderer " << static_cast<long>(build_ms_)
         << " ms, first frame " << static_cast<long>(first_frame_ms_) << " ms, "
         << programs_->compiles() - compiles_before_ << " of " << programs_->size() << " programs linked";
    // Process CPU time (every thread, the driver's too) from the conversion's start: what the
    // reload costs on a machine with a core to spare, whatever else the machine is running.
    if (status_.generation > 1)
      log_ << "; " << static_cast<long>(1000.0 * static_cast<double>(std::clock() - reload_cpu_began_) / CLOCKS_PER_SEC)
           << " ms of CPU";
    log_ << ")\n";
    log_.flush();
  }

  void update_values(Clock::time_point now) {
    if (subscriber_) {
      for (int round = 0; round < 16 && subscriber_->poll(std::chrono::milliseconds(0)); ++round) {
      }
      values_ = subscriber_->signals();  // what the scene and the (read-only) controls show
      if (subscriber_->link_up() != status_.link_up) {
        status_.link_up = subscriber_->link_up();
        ui_changed_ = true;
        log_ << "meter-preview: link " << options_.link << (status_.link_up ? " up" : " down (failsafe look)") << "\n";
        log_.flush();
      }
    } else if (player_) {
      if (input_.restart_playback) play_began_ = now;
      input_.restart_playback = false;
      status_.play_t = std::chrono::duration<double>(now - play_began_).count();
      player_->state_at(status_.play_t, values_);
    }
  }

  // The values -> bindings -> the engine's frame (skipped by the engine when nothing changed).
  // Returns true when the engine drew a new frame.
  bool step_scene(double dt) {
    if (!shown_) return false;
    const bool link_up = subscriber_ ? subscriber_->link_up() : !input_.link_lost;
    // Set and played states are states, not motion: jump to them as meter-view --set does; the
    // link's values move with the bindings' smoothing, as in meter-view.
    shown_->pipeline.evaluate(values_, link_up, subscriber_ ? dt : -1.0);
    const auto timing = shown_->pipeline.render(engine::FrameRequest{}).timing;
    if (!timing.drawn) return false;
    status_.render_ms = timing.update_ms + timing.submit_ms + timing.gpu_readback_ms;
    if (awaiting_screen_) first_frame_ms_ = status_.render_ms;
    return true;
  }

  // The engine's frame 1:1 at the top left, the panel beside it.
  void draw_window() {
    const auto& gl = window_->gpu().gl();
    const WindowSize fb = window_->framebuffer_size();
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    gl.Viewport(0, 0, fb.width, fb.height);
    gl.Disable(GL_SCISSOR_TEST);
    gl.ClearColor(0.1f, 0.1f, 0.1f, 1.0f);
    gl.Clear(GL_COLOR_BUFFER_BIT);
    int scene_width = 640;
    if (shown_) {
      blit_->draw(shown_->renderer.resolved_target(), 0, 0, fb.height);
      scene_width = shown_->renderer.width();
    }
    ui_->begin_frame();
    if (draw_controls_panel(scene_width, options_.panel_width, fb.height, status_, controls_, values_, input_))
      ui_changed_ = true;
    ui_->end_frame();
  }

  bool fits(WindowSize fb) const {
    return fb.width >= shown_->renderer.width() + options_.panel_width && fb.height >= shown_->renderer.height();
  }

  // The scene area of the frame about to be shown, read from the window's framebuffer.
  int screenshot() {
    if (!shown_) {
      log_ << "meter-preview: error: --screenshot: no scene is on screen (the first conversion failed)\n";
      return 1;
    }
    try {
      const auto image = window_->read_back(0, 0, shown_->renderer.width(), shown_->renderer.height());
      platform::write_png(image, options_.screenshot);
      return 0;
    } catch (const std::exception& e) {
      log_ << "meter-preview: error: --screenshot: " << e.what() << "\n";
      return 1;
    }
  }

  const PreviewOptions& options_;
  std::ostream& log_;
  SceneReloader reloader_;
  FileWatcher watcher_;
  protocol::SignalTable values_;
  std::optional<ValuesPlayer> player_;
  std::optional<protocol::Subscriber> subscriber_;
  std::unique_ptr<PreviewWindow> window_;
  std::unique_ptr<platform::FrameBlit> blit_;
  std::unique_ptr<UiLayer> ui_;
  std::unique_ptr<platform::ProgramCache> programs_;  // outlives every shown scene, not the window
  std::unique_ptr<ShownScene> shown_;
  std::vector<SignalControl> controls_;
  PanelStatus status_;
  PanelInput input_;
  Clock::time_point play_began_{}, save_time_{};
  bool awaiting_screen_ = false;
  bool ui_changed_ = true;  // the panel shows something new: draw the window
  double build_ms_ = 0.0, first_frame_ms_ = 0.0;  // the new scene's renderer and first frame
  std::clock_t reload_cpu_began_ = 0;
  std::size_t compiles_before_ = 0;  // the program cache's link count when the shown scene was made
};

}  // namespace

int run_preview(const PreviewOptions& options, std::ostream& log) {
  runner::install_stop_handlers();
  try {
    protocol::use_catalog_option(options.catalog);  // before the scene: its bindings name catalog signals
    PreviewLoop loop(options, log);
    return loop.run();
  } catch (const std::exception& e) {
    log << "meter-preview: error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace meter::preview
