// meter-view's whole run: the offline mode without a link, the live loop with one.
#pragma once

#include <ostream>

#include "meter/runner/view_options.hpp"

namespace meter::runner {

// The exit status when the display (--output) went away: the compositor closed the connection or
// the window.
inline constexpr int kExitDisplayLost = 3;

// Returns the exit status: 0, 1 after "meter-view: error: <message>" on `log`, or
// kExitDisplayLost.
int run_view(const ViewOptions& options, std::ostream& log);

}  // namespace meter::runner
