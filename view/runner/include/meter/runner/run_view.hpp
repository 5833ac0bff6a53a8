// meter-view's whole run: the offline mode without a link, the live loop with one.
#pragma once

#include <ostream>

#include "meter/runner/view_options.hpp"

namespace meter::runner {

// Returns the exit status: 0, or 1 after "meter-view: error: <message>" on `log`.
int run_view(const ViewOptions& options, std::ostream& log);

}  // namespace meter::runner
