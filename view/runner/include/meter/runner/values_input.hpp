// Offline signal values: `--set NAME=VALUE[@status]` and the values CSV (`--values F --at T`).
// Both fill a protocol::SignalTable, the state the bindings read (signals never named stay at the
// table's resting NotAvailable). Errors (ViewError) name where the text came from ("--set",
// "drive.csv:7") and what was expected.
#pragma once

#include <istream>
#include <string>
#include <vector>

#include "meter/protocol/signal_table.hpp"

namespace meter::runner {

// NAME=VALUE (VALUE a finite number, or any text for Text signals), optionally NAME=VALUE@status
// (valid, timed-out, invalid, not-available; valid when left out). Replaces the whole state of
// NAME in `values` (a number leaves no text, a text value 0). `where` prefixes errors.
void parse_set(const std::string& arg, protocol::SignalTable& values, const std::string& where);

// CSV rows "time,signal,value[,status]" (a header on the first line, blank lines and # comments
// are allowed); the state at time `t` (seconds) is, per signal, the last row with time <= t.
// Rows after `t` are not checked beyond their time. The first bad row throws.
void read_values_csv(std::istream& in, const std::string& name, double t, protocol::SignalTable& values);
// One row of a values CSV, checked.
struct ValuesRow {
  double t = 0.0;
  protocol::SignalId id{};
  protocol::SignalState state;
};
// Every row of a values CSV, checked, in file order (for a player that moves through the file's
// times without reading it again). The first bad row throws.
std::vector<ValuesRow> parse_values_csv(std::istream& in, const std::string& name);
// The state at time `t` from parsed rows, as read_values_csv gives it from the text.
void apply_values_at(const std::vector<ValuesRow>& rows, double t, protocol::SignalTable& values);
// The same from a file; a file that cannot be opened throws.
void load_values_csv(const std::string& path, double t, protocol::SignalTable& values);

}  // namespace meter::runner
