#include "meter/platform/backend.hpp"

#include <string>

#include "backends.hpp"
#include "meter/protocol/ascii_case.hpp"

namespace meter::platform {

std::string_view to_string(BackendKind kind) {
  switch (kind) {
    case BackendKind::Egl: return "egl";
    case BackendKind::OSMesa: return "osmesa";
  }
  return "unknown";
}

std::optional<BackendKind> parse_backend_kind(std::string_view text) {
  if (protocol::equals_ignoring_case(text, "egl")) return BackendKind::Egl;
  if (protocol::equals_ignoring_case(text, "osmesa")) return BackendKind::OSMesa;
  return std::nullopt;
}

std::unique_ptr<GpuBackend> create_backend(BackendKind kind, const BackendOptions& options) {
  switch (kind) {
    case BackendKind::Egl: return detail::create_egl_backend(options);
    case BackendKind::OSMesa: return detail::create_osmesa_backend(options);
  }
  throw BackendError("create_backend: unknown backend kind " +
                     std::to_string(static_cast<int>(kind)) + " (expected egl or osmesa)");
}

}  // namespace meter::platform
