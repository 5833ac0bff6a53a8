// Page switching: the requested page starts its transition clip; both pages are shown until
// the clip has played.
#include <algorithm>
#include <utility>

#include "meter/engine/evaluation/scene_features.hpp"

namespace meter::engine {

PageSwitcher::PageSwitcher(int pages, int initial, std::vector<double> transition_s)
    : pages_(pages), current_(initial), previous_(initial), duration_s_(std::move(transition_s)) {
  duration_s_.resize(static_cast<std::size_t>(pages_), 0.0);
}

void PageSwitcher::update(std::optional<int> page, double dt) {
  if (running_) {
    elapsed_s_ += std::max(dt, 0.0);
    if (dt < 0 || elapsed_s_ >= duration_s_[static_cast<std::size_t>(current_)]) running_ = false;
  }
  if (!page || *page < 0 || *page >= pages_ || *page == current_) return;
  // A request during a transition starts the new one from the page being entered.
  previous_ = current_;
  current_ = *page;
  elapsed_s_ = 0.0;
  running_ = dt >= 0 && duration_s_[static_cast<std::size_t>(current_)] > 0;
}

std::optional<double> PageSwitcher::transition() const {
  if (!running_) return std::nullopt;
  return std::clamp(elapsed_s_ / duration_s_[static_cast<std::size_t>(current_)], 0.0, 1.0);
}

bool PageSwitcher::shown(int page) const { return page == current_ || (running_ && page == previous_); }

}  // namespace meter::engine
