// frames.csv: one line per dumped PNG with the bound signals as drawn. Columns: frame, time_s,
// png, link_up, drawn; per bound signal (first binding of each) <signal>, <signal>.status,
// <signal>.failsafe; per text binding <node>.text, the exact text drawn, quoted (RFC 4180); then
// per text binding <node>.value, the value it formatted; with the integrity monitor on, last:
// integrity_faults (this frame's), integrity_total (since start), integrity_fault (this frame's
// first fault: region, expected, seen; quoted); with the frame-rate governor on, last:
// predicted_ms, measured_ms (the governor's prediction for the frame and its measured time),
// units_reduced (draw units below full quality), msaa, scale (the global rung), reduced (those
// units and their levels, "name=shading/lodN ..."; quoted); with a display (--output), last:
// presented_ns (CLOCK_MONOTONIC: when the frame turned into light, from the display's presentation
// feedback) and refresh_seq (the output's refresh counter then; 0 where it keeps none), both empty
// for a frame never shown. Such rows wait for their frame's feedback (PresentationRows: at most
// 1 s), in frame order.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/pipeline/frame_governor.hpp"
#include "meter/runner/presentation_rows.hpp"

namespace meter::runner {

// The integrity monitor's cells of one row (meter/runner/integrity_stage.hpp).
struct IntegrityCells {
  std::uint64_t faults = 0, total = 0;
  std::string first;
};

// The frame-rate governor's cells of one row (meter/engine/pipeline/frame_governor.hpp); also in the
// timing CSV.
using GovernorCells = engine::GovernorCells;
inline constexpr const char* kGovernorColumns = "predicted_ms,measured_ms,units_reduced,msaa,scale,reduced";
// ",<cells>" in kGovernorColumns' order.
std::string governor_cells_text(const GovernorCells& cells);

class FramesCsv : public PresentationHeldCsv {
 public:
  // Writes the header for the scene's bindings (and the integrity columns when `integrity`).
  // Throws ViewError when the file cannot be written.
  // With `governor`, the governor's columns next; with `presentation` (a display), the display's
  // columns last and each row held until its frame's feedback (the display's sink tells this
  // listener).
  FramesCsv(const std::filesystem::path& file, const std::vector<engine::Binding>& bindings, bool integrity = false,
            bool governor = false, bool presentation = false);

  // `states`: BindingEvaluator::states() after the update the frame was rendered with, one per
  // binding. Flushed at once, or with a display once its frame's feedback came (a reader may
  // follow the file while the view runs).
  // `integrity`: the frame's monitor cells (written when the header has the columns; none = 0).
  void row(std::uint64_t frame, double t, const std::string& png, bool link_up, bool drawn,
           const std::vector<engine::BindingState>& states, const IntegrityCells* integrity = nullptr,
           const GovernorCells* governor = nullptr);

 private:
  void cells(std::ostream& out, std::uint64_t frame, double t, const std::string& png, bool link_up, bool drawn,
             const std::vector<engine::BindingState>& states, const IntegrityCells* integrity,
             const GovernorCells* governor) const;
  PresentationRows::Write writer() override;

  std::ofstream out_;
  std::vector<std::size_t> columns_;       // binding index per signal column group
  std::vector<std::size_t> text_columns_;  // binding index per text column
  bool integrity_ = false;
  bool governor_ = false;
};

// RFC 4180 quoting: texts may hold commas or quotes (a map entry, a designer's format string).
std::string csv_quoted(const std::string& text);

}  // namespace meter::runner
