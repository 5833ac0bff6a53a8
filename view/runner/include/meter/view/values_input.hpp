// Offline signal values: `--set NAME=VALUE[@status]` and the values CSV (`--values F --at T`).
// Errors (ViewError) name where the text came from ("--set", "drive.csv:7") and what was expected.
#pragma once

#include <istream>
#include <string>

#include "meter/view/signal_values.hpp"

namespace meter::view {

// NAME=VALUE (VALUE a finite number, or any text for Text signals), optionally NAME=VALUE@status
// (valid, timed-out, invalid, not-available; valid when left out). Sets values[id of NAME].
// `where` prefixes errors.
void parse_set(const std::string& arg, SignalValues& values, const std::string& where);

// CSV rows "time,signal,value[,status]" (a header on the first line, blank lines and # comments
// are allowed); the state at time `t` (seconds) is, per signal, the last row with time <= t.
// Rows after `t` are not checked beyond their time. The first bad row throws.
void read_values_csv(std::istream& in, const std::string& name, double t, SignalValues& values);
// The same from a file; a file that cannot be opened throws.
void load_values_csv(const std::string& path, double t, SignalValues& values);

}  // namespace meter::view
