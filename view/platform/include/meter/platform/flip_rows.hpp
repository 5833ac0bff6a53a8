// The one row flip of the view: GL reads rows bottom-up (glReadPixels), an Image holds them
// top-down. Used by RenderTarget's reads and by the PNG writer for frames read through
// pixel-pack buffers.
#pragma once

#include "meter/platform/image.hpp"

namespace meter::platform {

// Reverses the row order of `image` in place (its rows tightly packed, width * 4 bytes).
void flip_rows(Image& image);

}  // namespace meter::platform
