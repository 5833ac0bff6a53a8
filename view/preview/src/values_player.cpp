#include "meter/preview/values_player.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>

#include "meter/runner/values_input.hpp"
#include "meter/runner/view_error.hpp"

namespace meter::preview {

ValuesPlayer::ValuesPlayer(const std::string& text, std::string name) : name_(std::move(name)) {
  // Every row is checked and parsed once here; playback only picks rows by time.
  std::istringstream in(text);
  rows_ = runner::parse_values_csv(in, name_);
  for (const auto& r : rows_) duration_ = std::max(duration_, r.t);
}

ValuesPlayer ValuesPlayer::load(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw runner::ViewError(path + ": cannot open values CSV");
  std::ostringstream text;
  text << in.rdbuf();
  return ValuesPlayer(text.str(), path);
}

void ValuesPlayer::state_at(double t, protocol::SignalTable& values) const {
  runner::apply_values_at(rows_, t, values);
}

}  // namespace meter::preview
