#include "meter/platform/display.hpp"

#include "backends.hpp"

namespace meter::platform {

std::unique_ptr<DisplayBackend> open_display(const DisplayOptions& options) {
  if (options.width <= 0 || options.height <= 0)
    throw BackendError("display: a frame size is needed (got " + std::to_string(options.width) + "x" +
                       std::to_string(options.height) + ")");
  if (options.target == "wayland" || options.target.rfind("wayland:", 0) == 0)
    return detail::create_wayland_display(options);
  if (options.target == "drm" || options.target.rfind("drm:", 0) == 0) return detail::create_drm_display(options);
  throw BackendError("--output: unknown display '" + options.target +
                     "' (expected offscreen, wayland, wayland:SOCKET, drm or drm:/dev/dri/cardN)");
}

}  // namespace meter::platform
