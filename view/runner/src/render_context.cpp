#include "meter/runner/render_context.hpp"

#include <system_error>

#include "meter/runner/option_units.hpp"
#include "meter/runner/view_error.hpp"

namespace meter::runner {
namespace {

std::unique_ptr<platform::GpuBackend> backend_named(const std::string& name) {
  const auto kind = platform::parse_backend_kind(name);
  if (!kind) throw ViewError("--backend: unknown backend \"" + name + "\" (egl or osmesa)");
  return platform::create_backend(*kind);
}

engine::RendererOptions renderer_options(const ViewOptions& options) {
  engine::RendererOptions ro;
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
      backend(backend_named(options.backend)),
      renderer(*backend, scene, renderer_options(options)),
      pipeline(scene, renderer),
      governed(renderer, options, log) {
  if (options.info) {
    log << "meter-view: " << renderer.backend_info() << "; " << scene.draws.size() << " draws, "
        << scene.programs.size() << " programs\n";
  }
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw ViewError(options.out_dir + ": cannot create output directory: " + ec.message());
  timing = TimingCsv(options.timing_csv, governed.governing());
}

}  // namespace meter::runner
