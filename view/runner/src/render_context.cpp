#include "meter/runner/render_context.hpp"

#include <cstdlib>
#include <system_error>

#include "meter/runner/display_sink.hpp"
#include "meter/runner/option_units.hpp"
#include "meter/runner/view_error.hpp"

namespace meter::runner {
namespace {

// The offscreen backend --backend names, or the display --output names (its own EGL context, the
// frame's size: --size or the scene config's).
std::unique_ptr<platform::GpuBackend> backend_for(const ViewOptions& options, const engine::Scene& scene) {
  if (options.output != "offscreen") {
    if (options.backend != "egl")
      throw ViewError("--output " + options.output + ": a display renders through EGL, not --backend " + options.backend);
    platform::DisplayOptions d;
    d.target = options.output;
    d.drm_modeset = options.drm_modeset;
    d.width = scene.config.size[0], d.height = scene.config.size[1];
    if (!options.size.empty()) std::tie(d.width, d.height) = parse_size(options.size);
    return platform::open_display(d);
  }
  const auto kind = platform::parse_backend_kind(options.backend);
  if (!kind) throw ViewError("--backend: unknown backend \"" + options.backend + "\" (egl or osmesa)");
  return platform::create_backend(*kind);
}

// --program-cache: off, a directory, or (empty) the XDG default; null when off or no default exists.
std::unique_ptr<engine::ProgramBinaryCache> program_binaries_for(const ViewOptions& options, std::ostream& log) {
  if (options.program_cache == "off") return nullptr;
  std::filesystem::path dir = options.program_cache;
  if (dir.empty()) dir = engine::default_program_cache_directory(std::getenv("XDG_CACHE_HOME"), std::getenv("HOME"));
  if (dir.empty()) return nullptr;
  return std::make_unique<engine::ProgramBinaryCache>(dir, log);
}

engine::RendererOptions renderer_options(const ViewOptions& options, engine::ProgramBinaryCache* binaries) {
  engine::RendererOptions ro;
  ro.program_binaries = binaries;
  ro.msaa = options.msaa;
  ro.partial_redraw = !options.full_redraw;
  if (!options.size.empty()) std::tie(ro.width, ro.height) = parse_size(options.size);
  return ro;
}

}  // namespace

RenderContext::RenderContext(const ViewOptions& options, std::ostream& log)
    : started(std::chrono::steady_clock::now()),
      out_dir(options.out_dir),
      scene(engine::read_package(options.scene_path)),
      backend((package_read = std::chrono::steady_clock::now(), backend_for(options, scene))),
      display(dynamic_cast<platform::DisplayBackend*>(backend.get())),
      program_binaries((backend_opened = std::chrono::steady_clock::now(), program_binaries_for(options, log))),
      renderer(*backend, scene, renderer_options(options, program_binaries.get())),
      pipeline(scene, renderer),
      governed(renderer, options, log) {
  renderer_made = std::chrono::steady_clock::now();
  if (options.info) {
    const auto ms = [](auto from, auto to) { return std::chrono::duration<double, std::milli>(to - from).count(); };
    log << "meter-view: start-up: package read " << ms(started, package_read) << " ms, "
        << (display ? "display opened (connect, EGL) " : "backend opened (EGL) ") << ms(package_read, backend_opened)
        << " ms, renderer (targets, programs, uploads, text) " << ms(backend_opened, renderer_made) << " ms\n";
    log << "meter-view: " << renderer.backend_info() << "; " << scene.draws.size() << " draws, "
        << scene.programs.size() << " programs\n";
    log << "meter-view: " << renderer.programs_linked() << " programs linked in " << renderer.program_link_ms() << " ms";
    if (program_binaries) {
      const auto& c = program_binaries->counts();
      log << "; program cache " << program_binaries->directory().string() << ": " << c.loaded << " loaded, "
          << c.compiled << " compiled, " << c.refused << " refused, " << c.stored << " stored";
    }
    log << "\n";
  }
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw ViewError(options.out_dir + ": cannot create output directory: " + ec.message());
  timing = TimingCsv(options.timing_csv, governed.governing(), display != nullptr);
  if (display) {
    display_sink = std::make_unique<DisplaySink>(*this, log);
    display_sink->add_listener(timing);
    if (options.info) {
      log << "meter-view: display: " << display->display_info() << "\n";
      display_sink->log_each_frame();
    }
  }
}

RenderContext::~RenderContext() = default;

}  // namespace meter::runner
