#include "meter/engine/pipeline/frame_pipeline.hpp"

#include <chrono>

#include "meter/protocol/trace_events.hpp"

namespace meter::engine {

FramePipeline::FramePipeline(const Scene& scene, Renderer& renderer) : evaluator_(scene), renderer_(renderer) {}

void FramePipeline::add_sink(FrameSink& sink) { sinks_.push_back(&sink); }

bool FramePipeline::evaluate(const protocol::SignalTable& signals, bool link_up, double dt) {
  record_ = FrameRecord{};
  record_.evaluate_began_realtime_ns = protocol::realtime_now_ns();
  record_.evaluate_began_ns = protocol::monotonic_now_ns();
  record_.link_up = link_up;
  const bool changed = evaluator_.update(signals, link_up, dt);  // read in place, no copy
  if (changed) renderer_.apply(evaluator_.outputs());
  return changed;
}

const FrameRecord& FramePipeline::render(const FrameRequest& request) {
  record_.request = request;
  for (FrameSink* s : sinks_) s->before_frame(request.frame);
  record_.render_began_ns = protocol::monotonic_now_ns();
  const governor::FrameLoad& planned = renderer_.plan(request.force, request.read);
  std::optional<governor::QualityChoice> choice;
  if (governor_) choice = governor_->choose(planned);
  record_.timing = renderer_.draw(choice);
  if (governor_) governor_->rendered(record_.timing, record_.render_began_ns);
  record_.render_ended_realtime_ns = protocol::realtime_now_ns();
  record_.render_ended_ns = protocol::monotonic_now_ns();
  record_.states = &evaluator_.states();
  record_.governor = governor_ ? governor_->cells() : nullptr;
  for (FrameSink* s : sinks_) s->on_drawn(record_);
  for (FrameSink* s : sinks_) s->on_frame(record_);
  return record_;
}

void FramePipeline::finish() {
  for (FrameSink* s : sinks_) s->finish();
}

}  // namespace meter::engine
