// Online re-estimation of the model's scales over a window of frames (online_estimate.hpp).
#include "meter/engine/governor/online_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "governor/robust_lsq.hpp"

namespace meter::engine::governor {
namespace {

// The two parts must be this far from proportional over the window (1 - cos^2 of the angle
// between the columns) before they are told apart; below, both take the common ratio.
constexpr double kMinIndependence = 0.05;

double clamp_scale(double s) {
  return std::clamp(s, OnlineEstimate::kMinScale, OnlineEstimate::kMaxScale);
}

}  // namespace

OnlineEstimate::OnlineEstimate(int window) : window_(window) {
  if (window < kMinPoints)
    throw std::invalid_argument("online estimate: window " + std::to_string(window) + " frames, expected >= " +
                                std::to_string(kMinPoints));
}

bool OnlineEstimate::add(const PredictionParts& predicted, double measured_ms) {
  const double total = predicted.pixel_ms + predicted.fixed_ms;
  if (!std::isfinite(measured_ms) || !(measured_ms > 0) || !std::isfinite(total) || !(total > 0) ||
      !(predicted.pixel_ms >= 0) || !(predicted.fixed_ms >= 0))
    return false;
  frames_.push_back({predicted.pixel_ms, predicted.fixed_ms, measured_ms});
  while (int(frames_.size()) > window_) frames_.pop_front();
  refit();
  return true;
}

double OnlineEstimate::upper_ratio(double share, double min_predicted_ms) const {
  std::vector<double> ratios;
  ratios.reserve(frames_.size());
  for (const Frame& f : frames_) {
    const double fitted = scale_.pixel * f.pixel_ms + scale_.fixed * f.fixed_ms;
    if (fitted >= min_predicted_ms && fitted > 0) ratios.push_back(f.measured_ms / fitted);
  }
  if (int(ratios.size()) < kMinSpreadPoints || !(share >= 0 && share < 1)) return 1.0;
  const auto k = static_cast<std::ptrdiff_t>(std::lround((1.0 - share) * double(ratios.size() - 1)));
  std::nth_element(ratios.begin(), ratios.begin() + k, ratios.end());
  const double q = ratios[std::size_t(k)];
  return std::isfinite(q) ? std::max(1.0, q) : 1.0;
}

void OnlineEstimate::reset() {
  frames_.clear();
  scale_ = {};
  rejected_ = 0;
}

void OnlineEstimate::refit() {
  if (int(frames_.size()) < kMinPoints) {
    scale_ = {};
    rejected_ = 0;
    return;
  }
  std::vector<robust::Row> rows;
  std::vector<double> ratios;
  rows.reserve(frames_.size());
  ratios.reserve(frames_.size());
  double max_ms = 0;
  for (const Frame& f : frames_) {
    rows.push_back({f.pixel_ms, f.fixed_ms, f.measured_ms});
    ratios.push_back(f.measured_ms / (f.pixel_ms + f.fixed_ms));
    max_ms = std::max(max_ms, f.measured_ms);
  }
  // The median ratio ignores any minority of outlier frames; trimming from it keeps that property
  // for the least-squares refinement.
  const double start = robust::median(ratios);
  const double sigma_floor = 1e-6 * max_ms;
  robust::Trimmed common = robust::trimmed_fit(rows, {start, start}, sigma_floor, true, kMinIndependence);
  const robust::Trimmed* t = &common;
  robust::Trimmed split;
  if (robust::least_squares(rows, common.keep, kMinIndependence)) {
    split = robust::trimmed_fit(rows, common.coefs, sigma_floor, false, kMinIndependence);
    if (split.coefs.c1 > 0 && split.coefs.c2 > 0) t = &split;
  }
  scale_ = {clamp_scale(t->coefs.c1), clamp_scale(t->coefs.c2)};
  if (!std::isfinite(scale_.pixel) || !std::isfinite(scale_.fixed)) scale_ = {};
  rejected_ = t->rejected;
}

}  // namespace meter::engine::governor
