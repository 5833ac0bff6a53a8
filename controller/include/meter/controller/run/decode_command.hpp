// meter-controller decode: a recorded CAN log through a DBC to CSV.
#pragma once

#include <iosfwd>
#include <string>

namespace meter::controller {

// decode: a candump log + DBC -> CSV rows "timestamp,message,signal,raw,physical,unit,status".
// With a mapping, only the signals the mapping uses are written.
// strict: refuse every DBC quirk (docs/dbc.md).
int decode_command(const std::string& dbc, const std::string& log, const std::string& map, std::ostream& out,
                   std::ostream& err, bool strict = false);

}  // namespace meter::controller
