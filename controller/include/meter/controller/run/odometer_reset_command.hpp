// meter-controller odometer-reset: accept a refused odometer state again.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>

namespace meter::controller {

// odometer-reset: the explicit acceptance of a refused odometer state (both copies damaged, or a
// copy put back from an older state). Rewrites both copies in state_dir with km (whole kilometres
// or fractions), or without it with the largest distance any valid copy holds (never backwards).
// Returns 0, or 1 with the reason (no valid copy and no km given, an I/O error).
int odometer_reset_command(const std::string& state_dir, std::optional<double> km, std::ostream& out, std::ostream& err);

}  // namespace meter::controller
