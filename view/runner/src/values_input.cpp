#include "meter/runner/values_input.hpp"

#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <vector>

#include "meter/protocol/catalog.hpp"
#include "meter/runner/view_error.hpp"

namespace meter::runner {
namespace {

const protocol::SignalInfo& signal_named(const std::string& name, const std::string& where) {
  const auto* info = protocol::find_signal(name);
  if (!info) throw ViewError(where + ": \"" + name + "\" is not in the signal catalog");
  return *info;
}

struct LeadingNumber {
  double value = 0;
  std::size_t used = 0;  // characters of the text it took; 0 = the text does not start with one
};
LeadingNumber leading_number(const std::string& text) {
  LeadingNumber n;
  try {
    n.value = std::stod(text, &n.used);
  } catch (const std::exception&) {
    n.used = 0;
  }
  return n;
}

// The whole of `text` as a finite number.
std::optional<double> finite_number(const std::string& text) {
  const auto n = leading_number(text);
  if (n.used == 0 || n.used != text.size() || !std::isfinite(n.value)) return std::nullopt;
  return n.value;
}

std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) fields.push_back(cell);
  return fields;
}

struct Assignment {
  protocol::SignalId id = 0;
  protocol::SignalState state;
};

// NAME=VALUE[@status] as the signal it names and the whole state it gives it.
Assignment parse_assignment(const std::string& arg, const std::string& where) {
  auto eq = arg.find('=');
  if (eq == std::string::npos || eq == 0) throw ViewError(where + ": expected NAME=VALUE, got \"" + arg + "\"");
  const auto& info = signal_named(arg.substr(0, eq), where);
  std::string value = arg.substr(eq + 1);
  protocol::SignalState sv;
  sv.status = protocol::SignalStatus::Valid;
  auto at = value.rfind('@');
  if (at != std::string::npos) {
    auto st = protocol::status_from_string(value.substr(at + 1));
    if (!st) {
      throw ViewError(where + ": unknown status \"" + value.substr(at + 1) +
                      "\" (valid, timed-out, invalid, not-available)");
    }
    sv.status = *st;
    value = value.substr(0, at);
  }
  if (info.kind == protocol::SignalKind::Text) {
    sv.text = value;
  } else {
    auto v = finite_number(value);
    if (!v) throw ViewError(where + ": value \"" + value + "\" for " + std::string(info.name) + " is not a finite number");
    sv.value = *v;
  }
  return {info.id, std::move(sv)};
}

}  // namespace

void parse_set(const std::string& arg, protocol::SignalTable& values, const std::string& where) {
  auto a = parse_assignment(arg, where);
  values.set(a.id, std::move(a.state));
}

namespace {

// Calls `row` for every row with time <= t, in file order; rows after `t` are checked for their
// time only. The first bad row throws.
template <typename Row>
void for_each_row(std::istream& in, const std::string& name, double t, Row&& row) {
  std::string line;
  int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    const auto f = split_fields(line);
    const std::string where = name + ":" + std::to_string(lineno);
    const std::string time_text = f.empty() ? "" : f[0];
    if (leading_number(time_text).used == 0 && lineno == 1) continue;  // the header
    const auto rt = finite_number(time_text);
    if (!rt) throw ViewError(where + ": first column must be a time in seconds, got \"" + time_text + "\"");
    if (f.size() < 3 || f.size() > 4) throw ViewError(where + ": expected time,signal,value[,status]");
    if (*rt > t) continue;
    const std::string set = f[1] + "=" + f[2] + (f.size() == 4 ? "@" + f[3] : "");
    auto a = parse_assignment(set, where);
    row(ValuesRow{*rt, a.id, std::move(a.state)});
  }
}

// Per signal, the row with the latest time (of equal times, the later row) wins.
struct LatestRows {
  protocol::SignalTable& values;
  std::map<protocol::SignalId, double> row_time;
  void operator()(const ValuesRow& r) {
    if (!row_time.count(r.id) || row_time[r.id] <= r.t) {
      row_time[r.id] = r.t;
      values.set(r.id, r.state);
    }
  }
};

}  // namespace

void read_values_csv(std::istream& in, const std::string& name, double t, protocol::SignalTable& values) {
  LatestRows latest{values, {}};
  for_each_row(in, name, t, [&](ValuesRow&& r) { latest(r); });
}

std::vector<ValuesRow> parse_values_csv(std::istream& in, const std::string& name) {
  std::vector<ValuesRow> rows;
  for_each_row(in, name, std::numeric_limits<double>::infinity(), [&](ValuesRow&& r) { rows.push_back(std::move(r)); });
  return rows;
}

void apply_values_at(const std::vector<ValuesRow>& rows, double t, protocol::SignalTable& values) {
  LatestRows latest{values, {}};
  for (const auto& r : rows)
    if (r.t <= t) latest(r);
}

void load_values_csv(const std::string& path, double t, protocol::SignalTable& values) {
  std::ifstream in(path);
  if (!in) throw ViewError(path + ": cannot open values CSV");
  read_values_csv(in, path, t, values);
}

}  // namespace meter::runner
