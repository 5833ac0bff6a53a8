// The one frame pipeline every mode of meter-view and meter-preview runs:
//   state (a signal table) -> bindings (+ display features, scripts; BindingEvaluator) ->
//   scene evaluation -> frame plan (Renderer::plan: the planned load) -> the governor's choice
//   (FrameGovernor, a plain input) -> GL execution (Renderer::draw) -> frame output (the sinks).
// A mode is a policy over it: where the state comes from (the link, a recording, a values file,
// the preview's controls) and when a frame is due (its clock). Observers and outputs are
// FrameSinks added once; each frame reaches every one of them in the order they were added.
#pragma once

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
  // The mode ends: every sink finishes, in order.
  void finish();

  BindingEvaluator& evaluator() { return evaluator_; }
  const BindingEvaluator& evaluator() const { return evaluator_; }
  const FrameGovernor* governor() const { return governor_; }

 private:
  BindingEvaluator evaluator_;
  Renderer& renderer_;
  FrameGovernor* governor_ = nullptr;
  std::vector<FrameSink*> sinks_;
  FrameRecord record_;
};

}  // namespace meter::engine
