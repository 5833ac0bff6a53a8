// Internal: the two backend factories (one translation unit each, so EGL and OSMesa headers never
// meet outside their own file).
#pragma once

#include <memory>

#include "meter/platform/backend.hpp"

namespace meter::platform::detail {

std::unique_ptr<GpuBackend> create_egl_backend(const BackendOptions& options);
std::unique_ptr<GpuBackend> create_osmesa_backend(const BackendOptions& options);

}  // namespace meter::platform::detail
