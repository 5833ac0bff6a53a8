#include "meter/preview/values_player.hpp"

#include <fstream>
#include <limits>
#include <sstream>

#include "meter/view/values_input.hpp"
#include "meter/view/view_error.hpp"

namespace meter::preview {

ValuesPlayer::ValuesPlayer(std::string text, std::string name) : text_(std::move(text)), name_(std::move(name)) {
  // Reading to the end checks every row; the latest row time is the file's last state.
  protocol::SignalTable all;
  std::istringstream in(text_);
  view::read_values_csv(in, name_, std::numeric_limits<double>::infinity(), all);
  std::istringstream lines(text_);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] == '#') continue;
    try {
      std::size_t used = 0;
      const double t = std::stod(line, &used);
      if (used > 0 && line.find(',') == used && t > duration_) duration_ = t;
    } catch (const std::exception&) {
      // the header: read_values_csv accepted it above, it holds no time
    }
  }
}

ValuesPlayer ValuesPlayer::load(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw view::ViewError(path + ": cannot open values CSV");
  std::ostringstream text;
  text << in.rdbuf();
  return ValuesPlayer(text.str(), path);
}

void ValuesPlayer::state_at(double t, protocol::SignalTable& values) const {
  std::istringstream in(text_);
  view::read_values_csv(in, name_, t, values);
}

}  // namespace meter::preview
