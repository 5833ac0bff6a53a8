// The frame-rate governor: holds a target frame time with the best image it can (pure; no GL,
// no clock: the runner measures and reports).
//
// Each drawn frame: choose(load) predicts the current choice on this frame's load with the
// calibrated model corrected by the online estimate, and runs the greedy choice
// (greedy_choice.hpp) with
//     trigger = target_ms                 (lower when the current choice would miss the target)
//     budget  = (1 - headroom) x target_ms (what a lowered or raised choice must fit)
// so between the two is a dead band where nothing changes (hysteresis: a step up is taken only
// when the higher level's prediction stays under (1 - headroom) x target). A step up is made at
// most once every min_frames_between_changes drawn frames; a step down, when the current choice
// is predicted over the target, at once (a frame over the target is worse than a change).
// After the frame is drawn, observe(load, choice, measured_ms) feeds the online estimate.
//
// A step up that held its judged frame but is reversed by a step down within `window` drawn frames
// (the window's fit drifted back: each rung and level has its own error, one scale fits them in
// turn) did not last either: the wait before the next step up doubles from 2 x
// min_frames_between_changes (up to kMaxStepUpWait) at each such reversal, and ends once a step up
// has stayed for a window. A choice that would flap between two levels every few dozen frames
// settles instead (the picture does not flicker).
//
// A step up whose first frame (for a global rung: the frame after the one that made its targets)
// measures over the target is undone at the next frame (one frame over instead of the fast
// attack's three), and the wait before the next step up doubles (up to
// kMaxStepUpWait frames) until a step up holds for its wait: a level the model wrongly thinks
// fits is not tried again every few frames. An undone step up to a global rung also teaches the
// governor that rung's own error (measured / predicted: the common scale is one for every rung):
// the rung's cost is multiplied by it from then on, and moved halfway back to 1 each time a step
// up to the rung holds. observe() compares each frame with that corrected model, so the window
// and the fast attack learn only what is left.
//
// A frame that is also read back whole (FrameLoad::read_back: a dump) costs the readback on top of
// its drawing, the same at every quality. The governor learns that cost from the read-back frames
// (measured minus the corrected prediction, >= 0; the first sample, then halfway to each new one)
// and, while frames are being read back (one within the last `window` drawn frames, or this one),
// reserves it in every frame's prediction and both budgets (capped at half the target): the
// quality then holds on the dumped frames too, and a dump shows what its neighbours show instead of
// a dip. The window and the fast attack see a read-back frame's measurement less the readback.
//
// The spread. The model predicts a frame's mean time; on a shared machine single frames come out
// above it by a few to tens of percent (other processes, the rasterizer threads' scheduling), and a
// choice predicted just under the target misses it on every such frame. So the target is divided
// by the spread: the (1 - miss_share) quantile of measured / fitted over the window's frames that
// matter (fitted at least half the target; at least 20 of them, else 1), between 1 and
// kMaxSpread: a choice within target / spread misses the target on about miss_share of frames.
// Both the trigger and the budget are so divided.
//
// Fast attack, slow release: the window's fit follows a load step once it holds half the window.
// When the last fast_attack_frames drawn frames in a row each measured over the budget and more
// than (1 + headroom) x their prediction, the model is scaled by the least of those ratios until
// that stops, so the frame after such a run is already chosen for the new load; the way back up
// is the window's.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "meter/engine/governor/cost_model.hpp"
#include "meter/engine/governor/greedy_choice.hpp"
#include "meter/engine/governor/online_estimate.hpp"

namespace meter::engine::governor {

struct GovernorOptions {
  double target_ms = 16.7;
  double headroom = 0.05;              // in [0, 0.5]
  int min_frames_between_changes = 8;  // >= 0 (0: may change every frame)
  int window = 60;                     // online estimate window, frames (>= OnlineEstimate::kMinPoints)
  int fast_attack_frames = 3;          // >= 0 (0: off; the window alone moves the model)
  double miss_share = 0.02;            // in [0, 0.5): the share of frames allowed over the target
                                       // by the frame-to-frame spread (0: no spread margin)
};

struct ReducedUnit {
  int unit = 0;
  std::string name;
  UnitLevel level;
  bridge::ShadingModel shading = bridge::ShadingModel::PbrMetallicRoughness;
};

// For --stats and frames.csv.
struct GovernorState {
  std::uint64_t frames_chosen = 0;    // drawn frames choose() was asked about
  std::uint64_t frames_observed = 0;  // frames observe() accepted
  std::uint64_t changes = 0;          // choices that differed from the one before
  int frames_since_change = 0;
  double predicted_ms = 0.0;          // for the last choice, this frame's load, scaled
  double measured_ms = 0.0;           // last accepted measurement (0 before any)
  ModelScale scale;                   // the online correction in use (window x fast attack)
  double fast_attack = 1.0;           // the fast-attack factor in that scale (1: not attacking)
  double spread = 1.0;                // the target is divided by it (see above)
  std::uint64_t step_ups_undone = 0;  // step ups whose judged frame missed the target
  int step_up_wait = 0;               // drawn frames a step up waits for after a change now
  double readback_ms = 0.0;           // the learnt readback cost (0 before a read-back frame)
  bool readback_reserved = false;     // reserved in the last choice (frames are being read back)
  int global_rung = 0;                // index in CostModel::globals
  GlobalLevel global;
  std::vector<ReducedUnit> reduced;   // units not at full quality, in unit order
};

// "needle=gouraud/lod1 dial=pbr/lod2" (empty when every unit is at full quality).
std::string reduced_summary(const GovernorState& state);

class Governor {
 public:
  // Throws std::invalid_argument for a model without rungs, or options out of range
  // (target_ms not finite or <= 0, headroom outside [0, 0.5], negative min frames, small window).
  Governor(CostModel model, GovernorOptions options = {});

  // The choice to draw this frame with. A frame that is not drawn keeps the current choice (and
  // does not count toward the frames between changes). Non-finite pixel counts are read as
  // cost_model.hpp says; the prediction stays finite.
  QualityChoice choose(const FrameLoad& load);

  // After the frame drawn with `choice` (normally the last choose() result) took measured_ms;
  // `load` is the frame's load as drawn (when a changed choice made the renderer re-plan, the
  // re-planned load: the prediction it is compared with must describe the same work).
  // Ignored when measured_ms is not finite or <= 0 or the frame was not drawn. Throws
  // std::invalid_argument when the choice does not fit the model.
  void observe(const FrameLoad& load, const QualityChoice& choice, double measured_ms);

  double predicted_ms() const { return predicted_ms_; }
  const QualityChoice& current() const { return current_; }
  const CostModel& model() const { return model_; }
  const GovernorOptions& options() const { return options_; }
  GovernorState state() const;

 private:
  ModelScale scale() const;  // the window's fit x the fast-attack factor
  double fast_attack() const;
  double spread() const;
  static constexpr double kMaxSpread = 1.5;
  int judged_frame() const;  // frames after a step up whose measurement can undo it
  void set_rung_error(int rung, double error);
  double readback_reserve(const FrameLoad& load) const;  // what choose() adds for the readback

  CostModel model_;
  GovernorOptions options_;
  // model_ with each global rung's cost times its own error (rung_error_, >= 1), learnt from the
  // step ups to it that were undone; the choice is made on it.
  CostModel corrected_;
  std::vector<double> rung_error_;
  OnlineEstimate online_;
  std::deque<double> recent_ratios_;  // measured / predicted of the last drawn frames
  QualityChoice current_;
  std::optional<FrameLoad> last_full_load_;
  double predicted_ms_ = 0.0;
  double measured_ms_ = 0.0;
  std::uint64_t frames_chosen_ = 0, frames_observed_ = 0, changes_ = 0;
  int frames_since_change_ = 0;
  // Undoing a step up that missed the target, and the backoff before the next one.
  static constexpr int kMaxStepUpWait = 256;
  bool last_change_up_ = false, last_change_global_ = false, undo_pending_ = false;
  QualityChoice before_step_up_;
  std::uint64_t step_ups_undone_ = 0;
  int step_up_wait_ = 0;
  // A step up reversed by a step down within `window` frames: the wait before the next one.
  int frames_since_step_up_ = 1 << 30, late_backoff_ = 0;
  // The readback of dumped frames.
  bool readback_known_ = false, readback_reserved_ = false;
  double readback_ms_ = 0.0;
  int frames_since_readback_ = 1 << 30;
};

}  // namespace meter::engine::governor
