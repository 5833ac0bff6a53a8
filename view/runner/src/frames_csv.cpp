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
                     bool governor, bool presentation)
    : out_(create_output_file(file)), integrity_(integrity), governor_(governor) {
  if (presentation) set_holding();
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
  if (holding()) out_ << ",presented_ns,refresh_seq";
  out_ << "\n";
  out_.flush();  // a reader following the file sees the columns before the first row
}

void FramesCsv::row(std::uint64_t frame, double t, const std::string& png, bool link_up, bool drawn,
                    const std::vector<engine::BindingState>& states, const IntegrityCells* integrity,
                    const GovernorCells* governor) {
  if (!holding()) {
    cells(out_, frame, t, png, link_up, drawn, states, integrity, governor);
    out_ << "\n";
    out_.flush();
    return;
  }
  std::ostringstream text;
  cells(text, frame, t, png, link_up, drawn, states, integrity, governor);
  hold(frame, text.str(), 0);
}

void FramesCsv::cells(std::ostream& out, std::uint64_t frame, double t, const std::string& png, bool link_up,
                      bool drawn, const std::vector<engine::BindingState>& states, const IntegrityCells* integrity,
                      const GovernorCells* governor) const {
  out << frame << "," << std::fixed << std::setprecision(4) << t << "," << png << "," << link_up << "," << drawn;
  for (std::size_t i : columns_) {
    const auto& s = states.at(i);
    out << "," << std::setprecision(6) << s.value << "," << protocol::to_string(s.status) << "," << s.failsafe;
  }
  for (std::size_t i : text_columns_) out << "," << csv_quoted(states.at(i).text);
  for (std::size_t i : text_columns_) out << "," << std::setprecision(6) << states.at(i).value;
  if (integrity_) {
    const IntegrityCells none;
    const IntegrityCells& c = integrity ? *integrity : none;
    out << "," << c.faults << "," << c.total << "," << csv_quoted(c.first);
  }
  if (governor_) out << governor_cells_text(governor ? *governor : GovernorCells{});
}

PresentationRows::Write FramesCsv::writer() {
  return [this](const std::string& text, std::int64_t, const platform::PresentedFrame* shown) {
    out_ << text << ",";
    if (shown) out_ << shown->presented_ns << "," << shown->sequence;
    else out_ << ",";
    out_ << "\n";
    out_.flush();
  };
}

}  // namespace meter::runner
