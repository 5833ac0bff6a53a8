// What the EGL backends share: an EGL error's name and a look-up in an extension list.
#pragma once

#include <EGL/egl.h>

#include <string>
#include <string_view>

namespace meter::platform::detail {

std::string egl_error_name(EGLint error);
// Whether the space-separated `list` (an EGL_EXTENSIONS string; nullptr: none) holds `token`.
bool has_token(const char* list, std::string_view token);
void* egl_get_proc(const char* name);

}  // namespace meter::platform::detail
