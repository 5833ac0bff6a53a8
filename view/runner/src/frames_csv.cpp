#include "meter/runner/frames_csv.hpp"

#include <iomanip>
#include <set>
#include <sstream>

#include "meter/protocol/catalog.hpp"
#include "output_file.hpp"

namespace meter::runner {

std::string csv_quoted(const std::string& text) {
  std::string q = "\"";
  for (char c : text) {
    if (c == '"') q += '"';
    q += c;
  }
  return q + "\"";
}

std::string governor_cells_text(const GovernorCells& c) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(3) << "," << c.predicted_ms << "," << c.measured_ms << "," << c.units_reduced << ","
      << c.msaa << "," << std::setprecision(4) << c.scale << "," << csv_quoted(c.reduced);
  return out.str();
}

FramesCsv::FramesCsv(const std::filesystem::path& file, const std::vector<engine::Binding>& bindings, bool integrity,
                     bool governor)
    : out_(create_output_file(file)), integrity_(integrity), governor_(governor) {
  out_ << "frame,time_s,png,link_up,drawn";
  std::set<std::string> seen;
  for (std::size_t i = 0; i < bindings.size(); ++i) {
    const auto& b = bindings[i];
    if (seen.insert(b.signal).second) {
      columns_.push_back(i);
      out_ << "," << b.signal << "," << b.signal << ".status," << b.signal << ".failsafe";
    }
  }
  // A needle draws its smoothed value while a readout of the same signal draws the latest one,
  // so the signal's column alone cannot say what the readout showed: each text binding gets its
  // own column with the exact text drawn.
  for (std::size_t i = 0; i < bindings.size(); ++i) {
    const auto& b = bindings[i];
    if (b.kind == engine::BindingKind::Text) {
      text_columns_.push_back(i);
      out_ << "," << b.node << ".text";
    }
  }
  // The value each readout formatted (the latest, while the needle of the same signal may still
  // be smoothing towards it): meter-verify formats it again to know what the readout must show.
  for (std::size_t i : text_columns_) out_ << "," << bindings[i].node << ".value";
  if (integrity_) out_ << ",integrity_faults,integrity_total,integrity_fault";
  if (governor_) out_ << "," << kGovernorColumns;
  out_ << "\n";
}

void FramesCsv::row(std::uint64_t frame, double t, const std::string& png, bool link_up, bool drawn,
                    const std::vector<engine::BindingState>& states, const IntegrityCells* integrity,
                    const GovernorCells* governor) {
  out_ << frame << "," << std::fixed << std::setprecision(4) << t << "," << png << "," << link_up << "," << drawn;
  for (std::size_t i : columns_) {
    const auto& s = states.at(i);
    out_ << "," << std::setprecision(6) << s.value << "," << protocol::to_string(s.status) << "," << s.failsafe;
  }
  for (std::size_t i : text_columns_) out_ << "," << csv_quoted(states.at(i).text);
  for (std::size_t i : text_columns_) out_ << "," << std::setprecision(6) << states.at(i).value;
  if (integrity_) {
    const IntegrityCells none;
    const IntegrityCells& c = integrity ? *integrity : none;
    out_ << "," << c.faults << "," << c.total << "," << csv_quoted(c.first);
  }
  if (governor_) out_ << governor_cells_text(governor ? *governor : GovernorCells{});
  out_ << "\n";
  out_.flush();
}

}  // namespace meter::runner
