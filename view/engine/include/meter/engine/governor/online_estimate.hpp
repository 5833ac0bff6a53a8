// Online re-estimation of the cost model while running: from each drawn frame's predicted parts
// (the calibrated model's pixel part and fixed part for the load and choice it was drawn with) and
// its measured time, a robust least-squares fit over the last `window` frames of
//     measured = pixel_scale x pixel part + fixed_scale x fixed part,
// started from the median ratio measured / predicted and refined by trimmed least squares (frames
// more than 3 robust standard deviations off are dropped), so one outlier frame does not move it
// and a load step (another process taking a core) does once it holds half the window. When the
// window cannot separate the two parts (every frame has the same mix) both scales are the one
// common ratio. Scales are clamped to [kMinScale, kMaxScale].
#pragma once

#include <cstddef>
#include <deque>

#include "meter/engine/governor/cost_model.hpp"

namespace meter::engine::governor {

class OnlineEstimate {
 public:
  static constexpr double kMinScale = 0.05;
  static constexpr double kMaxScale = 20.0;
  static constexpr int kMinPoints = 4;  // fewer frames in the window: scale stays {1, 1}

  explicit OnlineEstimate(int window = 60);  // window >= kMinPoints, else std::invalid_argument

  // Adds one frame; ignored (returns false) when measured_ms is not finite or <= 0, or the
  // prediction is not positive and finite.
  bool add(const PredictionParts& predicted, double measured_ms);
  void reset();

  ModelScale scale() const { return scale_; }
  // How far over the fit the slow frames of the window come: of the frames whose fitted
  // prediction is at least min_predicted_ms, the (1 - share) quantile of measured / fitted
  // prediction (share 0.02: 98 % of those frames measured at most that many times their fit).
  // 1 when fewer than kMinSpreadPoints frames count; never below 1.
  static constexpr int kMinSpreadPoints = 20;
  double upper_ratio(double share, double min_predicted_ms) const;
  int points() const { return int(frames_.size()); }
  int window() const { return window_; }
  int rejected_last_fit() const { return rejected_; }  // frames the last fit dropped as outliers

 private:
  struct Frame {
    double pixel_ms, fixed_ms, measured_ms;
  };
  void refit();

  int window_;
  std::deque<Frame> frames_;
  ModelScale scale_;
  int rejected_ = 0;
};

}  // namespace meter::engine::governor
