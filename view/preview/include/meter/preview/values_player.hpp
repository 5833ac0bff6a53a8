// Plays a values CSV (the format of meter-view --values: "time,signal,value[,status]" rows) on
// the preview's clock: at playback time t every signal the file names holds its last row at or
// before t, the state meter-view --values FILE --at t renders.
#pragma once

#include <string>
#include <vector>

#include "meter/protocol/signal_table.hpp"
#include "meter/runner/values_input.hpp"

namespace meter::preview {

class ValuesPlayer {
 public:
  // `text` is the file's content, `name` where it came from (errors say "name:line"). Every row is
  // checked here, so a bad file is refused before playing (meter::runner::ViewError).
  ValuesPlayer(const std::string& text, std::string name);
  // Reads the file (ViewError when it cannot be opened or a row is bad).
  static ValuesPlayer load(const std::string& path);

  // Time of the last row: playback has reached the file's final state at and after it.
  double duration() const { return duration_; }
  const std::string& name() const { return name_; }
  // The state at playback time `t` seconds, written into `values` (signals the file never names
  // keep their state).
  void state_at(double t, protocol::SignalTable& values) const;

 private:
  std::vector<runner::ValuesRow> rows_;
  std::string name_;
  double duration_ = 0.0;
};

}  // namespace meter::preview
