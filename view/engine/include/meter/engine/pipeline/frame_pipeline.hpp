// The one frame pipeline every mode of meter-view and meter-preview runs:
//   state (a signal table) -> bindings (+ display features, scripts; BindingEvaluator) ->
//   scene evaluation -> frame plan (Renderer::plan: the planned load) -> the governor's choice
//   (FrameGovernor, a plain input) -> GL execution (Renderer::draw) -> frame output (the sinks).
// A mode is a policy over it: where the state comes from (the link, a recording, a values file,
// the preview's controls) and when a frame is due (its clock). Observers and outputs are
// FrameSinks added once; each frame reaches every one of them in the order they were added.
#pragma once

#include <chrono>
#include <optional>
#include <vector>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/pipeline/frame_governor.hpp"
#include "meter/engine/pipeline/frame_sink.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/protocol/signal_table.hpp"

namespace meter::engine {

class FramePipeline {
 public:
  // The pipeline owns the binding step (bindings, display features, scripts) of `scene`; the
  // renderer owns the scene step (evaluation, plan, GL execution). Both outlive the pipeline.
  FramePipeline(const Scene& scene, Renderer& renderer);

  // Observers and outputs, called in this order. Each outlives its use (the mode adding it).
  void add_sink(FrameSink& sink);
  // The quality input; nullptr (the default): the renderer keeps its quality.
  void set_governor(FrameGovernor* governor) { governor_ = governor; }

  // State -> bindings: one binding step over `signals` (dt: seconds since the last step, negative:
  // jump to the targets). The evaluator detects a change of its outputs once; only then are they
  // applied to the renderer, which marks the frame dirty. Returns whether they changed.
  bool evaluate(const protocol::SignalTable& signals, bool link_up, double dt);
  // Plan -> choice -> draw -> sinks, for the state last evaluated. The record stays valid until the
  // next evaluate() or render().
  const FrameRecord& render(const FrameRequest& request);
  // The mode ends: the frame in flight completes, then every sink finishes, in order.
  void finish();

  // The overlapped pipeline (CUBE's double buffer between the CPU stages and the GPU): a frame's
  // GL work executes, fenced, while the next frame's intake, bindings, evaluation and plan run on
  // this thread. The frame goes through in three calls a mode orders and meters: plan()
  // (Renderer::plan: no GL execution waited for), complete() (the frame in flight waited for and
  // handed to the sinks, on_drawn then on_frame, so every sink sees a frame that is drawn, before
  // the next one is submitted into the same target), draw() (the sinks' before_frame, the
  // governor's choice, Renderer::draw ending in a fence: the frame now in flight). One frame is in
  // flight at most. The records carry a copy of the states they were drawn from; a sink or
  // governor that reads the engine's own state of the frame it is handed (the renderer's planned
  // load) needs complete() before the next evaluate().
  void set_overlap(bool on);
  bool overlapped() const { return overlap_; }
  const governor::FrameLoad& plan(const FrameRequest& request);
  // nullptr when no frame is in flight; the record stays valid until the next complete().
  const FrameRecord* complete();
  void draw();
  // Whether the frame in flight has finished executing (true when none is), waiting at most `wait`
  // (it returns as soon as the frame finishes); while it has not, its FrameRecord::
  // gpu_busy_until_ns moves on to now; the first time it has, its render_ended stamps (the frame
  // drawn) are taken, not later when complete() hands it on.
  bool poll_in_flight(std::chrono::nanoseconds wait = std::chrono::nanoseconds(0));
  bool in_flight() const { return in_flight_.has_value(); }

  BindingEvaluator& evaluator() { return evaluator_; }
  const BindingEvaluator& evaluator() const { return evaluator_; }
  const FrameGovernor* governor() const { return governor_; }

 private:
  // The governor's choice for the load planned last (none without a governor); the plan is used up.
  std::optional<governor::QualityChoice> choose_planned();
  // A drawn frame to every sink: on_drawn, then on_frame, in the order added.
  void hand_on(const FrameRecord& r);

  BindingEvaluator evaluator_;
  Renderer& renderer_;
  FrameGovernor* governor_ = nullptr;
  std::vector<FrameSink*> sinks_;
  FrameRecord record_;
  // Overlapped: the frame executing (its record, with its own copy of the states drawn), the one
  // last completed (valid until the next complete()), and the planned load until draw().
  struct InFlight {
    FrameRecord record;
    std::vector<BindingState> states;
  };
  bool overlap_ = false;
  std::optional<InFlight> in_flight_;
  InFlight completed_;
  InFlight spare_;  // the buffers of the frame completed before, refilled for the next submission
  const governor::FrameLoad* planned_ = nullptr;
};

}  // namespace meter::engine
