#include "meter/engine/pipeline/frame_pipeline.hpp"

#include <chrono>
#include <stdexcept>
#include <utility>

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
  for (FrameSink* s : sinks_) s->before_frame(request.frame);
  plan(request);
  record_.timing = renderer_.draw(choose_planned());
  if (governor_) governor_->rendered(record_.timing, record_.render_began_ns);
  record_.render_ended_realtime_ns = protocol::realtime_now_ns();
  record_.render_ended_ns = protocol::monotonic_now_ns();
  record_.states = &evaluator_.states();
  record_.governor = governor_ ? governor_->cells() : nullptr;
  hand_on(record_);
  return record_;
}

std::optional<governor::QualityChoice> FramePipeline::choose_planned() {
  std::optional<governor::QualityChoice> choice;
  if (governor_) choice = governor_->choose(*planned_);
  planned_ = nullptr;
  return choice;
}

void FramePipeline::hand_on(const FrameRecord& r) {
  for (FrameSink* s : sinks_) s->on_drawn(r);
  for (FrameSink* s : sinks_) s->on_frame(r);
}

void FramePipeline::finish() {
  complete();
  for (FrameSink* s : sinks_) s->finish();
}

void FramePipeline::set_overlap(bool on) {
  overlap_ = on;
  renderer_.set_frame_end(on ? Renderer::FrameEnd::Fence : Renderer::FrameEnd::Finish);
}

const governor::FrameLoad& FramePipeline::plan(const FrameRequest& request) {
  record_.request = request;
  record_.render_began_ns = protocol::monotonic_now_ns();
  planned_ = &renderer_.plan(request.force, request.read);
  return *planned_;
}

const FrameRecord* FramePipeline::complete() {
  if (!in_flight_) return nullptr;
  // The frame handed on before gives its buffers to the next submission (no allocation per frame).
  std::swap(completed_, *in_flight_);
  spare_ = std::move(*in_flight_);
  in_flight_.reset();
  FrameRecord& r = completed_.record;
  r.states = &completed_.states;
  if (r.render_ended_ns == 0 && !renderer_.drawn_done()) {
    r.gpu_wait_ns = renderer_.wait_drawn();
    r.gpu_busy_until_ns = protocol::monotonic_now_ns();
  }
  renderer_.wait_drawn();  // done already: the fence is let go
  r.timing.gpu_readback_ms += static_cast<double>(r.gpu_wait_ns) / 1e6;
  if (r.render_ended_ns == 0) {  // not seen finished before: it is now
    r.render_ended_realtime_ns = protocol::realtime_now_ns();
    r.render_ended_ns = protocol::monotonic_now_ns();
  }
  if (governor_) {
    // The frame's own cost (its plan, submission and the wait for its execution), not the next
    // frame's intake and evaluation that ran while it executed.
    const auto own_ns = static_cast<std::int64_t>(r.timing.submit_ms * 1e6) + r.gpu_wait_ns;
    governor_->rendered(r.timing, r.render_ended_ns - own_ns);
    r.governor = governor_->cells();
  }
  hand_on(r);
  return &r;
}

void FramePipeline::draw() {
  if (!planned_) throw std::logic_error("FramePipeline::draw without plan()");
  complete();  // one frame in flight: the one before is handed on before this one is submitted
  for (FrameSink* s : sinks_) s->before_frame(record_.request.frame);  // after the frame before was checked
  const std::optional<governor::QualityChoice> choice = choose_planned();
  record_.draw_began_ns = protocol::monotonic_now_ns();
  record_.timing = renderer_.draw(choice);
  record_.submitted_ns = record_.gpu_busy_until_ns = protocol::monotonic_now_ns();
  const auto& states = evaluator_.states();
  spare_.record = record_;
  spare_.states.assign(states.begin(), states.end());
  in_flight_ = std::move(spare_);
}

bool FramePipeline::poll_in_flight(std::chrono::nanoseconds wait) {
  if (!in_flight_) return true;
  FrameRecord& r = in_flight_->record;
  if (r.render_ended_ns != 0) return true;
  if (renderer_.drawn_done(wait)) {  // first seen finished: the frame is drawn now, whenever it is handed on
    r.render_ended_realtime_ns = protocol::realtime_now_ns();
    r.render_ended_ns = protocol::monotonic_now_ns();
    return true;
  }
  r.gpu_busy_until_ns = protocol::monotonic_now_ns();
  return false;
}

}  // namespace meter::engine
