#include "meter/platform/backend.hpp"

#include <algorithm>
#include <cctype>
#include <string>

#include "backends.hpp"

namespace meter::platform {

std::string_view to_string(BackendKind kind) {
  switch (kind) {
    case BackendKind::Egl: return "egl";
    case BackendKind::OSMesa: return "osmesa";
  }
  return "unknown";
}

std::optional<BackendKind> parse_backend_kind(std::string_view text) {
  std::string lower(text);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower == "egl") return BackendKind::Egl;
  if (lower == "osmesa") return BackendKind::OSMesa;
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
