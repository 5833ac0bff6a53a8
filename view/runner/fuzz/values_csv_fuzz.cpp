// Fuzzes the values CSV reader (meter-view --values, meter-preview's values playback) as the view
// uses it: every row parsed and checked, the state taken at several times from the parsed rows and
// read again from the text, which must agree. A refusal is a ViewError naming the file; a crash,
// a sanitizer report, another exception, a non-finite value or a disagreement is a finding.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

#include "meter/protocol/catalog.hpp"
#include "meter/protocol/signal_table.hpp"
#include "meter/runner/values_input.hpp"
#include "meter/runner/view_error.hpp"

using namespace meter;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<runner::ValuesRow> rows;
  try {
    std::istringstream in(text);
    rows = runner::parse_values_csv(in, "fuzz.csv");
  } catch (const runner::ViewError& e) {
    if (std::string(e.what()).rfind("fuzz.csv", 0) != 0) std::abort();  // names the file
    return 0;
  }
  double last = 0;
  for (const auto& r : rows) {
    if (!std::isfinite(r.t) || !std::isfinite(r.state.value)) std::abort();
    if (protocol::find_signal(r.id) == nullptr) std::abort();
    last = r.t;
  }
  for (const double t : {-1.0, 0.0, last / 2, last, last + 1}) {
    protocol::SignalTable from_rows, from_text;
    runner::apply_values_at(rows, t, from_rows);
    std::istringstream again(text);
    runner::read_values_csv(again, "fuzz.csv", t, from_text);  // the same text: it must not throw now
    for (std::size_t i = 0; i < from_rows.size(); ++i) {
      const auto& a = from_rows.states()[i];
      const auto& b = from_text.states()[i];
      if (a.status != b.status || a.text != b.text || !(a.value == b.value || (a.value != a.value && b.value != b.value))) {
        std::abort();
      }
    }
  }
  return 0;
}
