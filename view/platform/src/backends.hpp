// Internal: the backend and display factories (one translation unit each, so EGL, OSMesa and
// window-system headers never meet outside their own file).
#pragma once

#include <memory>

#include "meter/platform/backend.hpp"
#include "meter/platform/display.hpp"

namespace meter::platform::detail {

std::unique_ptr<GpuBackend> create_egl_backend(const BackendOptions& options);
std::unique_ptr<GpuBackend> create_osmesa_backend(const BackendOptions& options);
std::unique_ptr<DisplayBackend> create_wayland_display(const DisplayOptions& options);
std::unique_ptr<DisplayBackend> create_drm_display(const DisplayOptions& options);

}  // namespace meter::platform::detail
