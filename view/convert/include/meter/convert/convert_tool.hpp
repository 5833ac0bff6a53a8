// What meter-convert does once its command line is parsed: load the scene config, convert the
// glTF, print the repairs, write the package and (with --report) the program and concatenation
// report. The executable is a thin shell over this.
#pragma once

#include <ostream>
#include <string>

namespace meter::convert {

struct ToolOptions {
  std::string input, config, output;
  std::string optimize = "on";  // "on" | "off"
  bool report = false, quiet = false, propose_groups = false;
  std::string catalog;  // signal catalog the config's bindings are checked against; empty = built in
  // GL backend the safety regions are measured on ("egl" | "osmesa"), or "off": no integrity table.
  std::string integrity = "egl";
  // "on": cheaper LOD and shading levels of every non-safety draw (meter/convert/levels.hpp); "off": none.
  std::string levels = "on";
  // meter-costs/1 file whose "concatenation" block feeds the merge break-even test; empty: none.
  std::string costs;
};

// Returns the process exit code (0 written, 1 error); `out` gets the report, `err` the repairs,
// the summary line and errors.
int run_convert_tool(const ToolOptions& options, std::ostream& out, std::ostream& err);

}  // namespace meter::convert
