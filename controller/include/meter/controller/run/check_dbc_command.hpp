// meter-controller check-dbc: a DBC's summary and lint report.
#pragma once

#include <iosfwd>
#include <string>

namespace meter::controller {

// check-dbc: parse a DBC, summarise it, print the lint report (counts, warnings by kind) and every
// problem with its file:line. 0 with warnings, 1 when it cannot be read or (strict) has any problem.
int check_dbc_command(const std::string& dbc, std::ostream& out, std::ostream& err, bool strict = false);

}  // namespace meter::controller
