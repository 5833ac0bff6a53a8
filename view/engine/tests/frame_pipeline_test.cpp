// The frame pipeline on the cluster (EGL): state -> bindings -> plan -> the governor's choice ->
// draw -> sinks, in that order; a state whose outputs did not change is not applied again and the
// frame is skipped; the governor's choice is a plain input drawn as a direct set_quality draws it;
// the overlapped pipeline (frames ended with a fence) hands every sink the frame drawn, with its own
// states, pixel for pixel as the sequential one.
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "meter/engine/pipeline/frame_pipeline.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/backend.hpp"
#include "meter/protocol/catalog.hpp"
#include "test_scenes.hpp"

using namespace meter;
using namespace meter::engine;

namespace {

RendererOptions pipeline_options() {
  RendererOptions o;
  o.width = 640, o.height = 240;
  return o;
}

protocol::SignalTable speed_state(double speed) {
  protocol::SignalTable values;
  const std::map<std::string, double> v = {{"Vehicle.Speed", speed}, {"Cluster.Telltale.TurnLeft", 1}};
  for (const auto& [name, x] : v)
    if (const auto* info = protocol::find_signal(name)) values.set(info->id, {x, protocol::SignalStatus::Valid, ""});
  return values;
}

// Records the calls every sink sees, tagged with the sink's name.
struct Recorder : FrameSink {
  Recorder(std::string name, std::vector<std::string>& calls) : name(std::move(name)), calls(calls) {}
  void before_frame(std::uint64_t frame) override { calls.push_back(name + " before " + std::to_string(frame)); }
  void on_drawn(const FrameRecord& f) override { calls.push_back(name + " drawn " + std::to_string(f.request.frame)); }
  void on_frame(const FrameRecord& f) override {
    calls.push_back(name + " frame " + std::to_string(f.request.frame));
    records.push_back(f);
  }
  void finish() override { calls.push_back(name + " finish"); }
  std::string name;
  std::vector<std::string>& calls;
  std::vector<FrameRecord> records;
};

// Chooses `choice` for every frame and keeps the loads it was asked with.
struct FixedGovernor : FrameGovernor {
  std::optional<governor::QualityChoice> choose(const governor::FrameLoad& planned) override {
    asked.push_back(planned);
    return choice;
  }
  void rendered(const FrameTiming& timing, std::int64_t) override { timings.push_back(timing); }
  const GovernorCells* cells() const override { return &cells_; }
  std::optional<governor::QualityChoice> choice;
  std::vector<governor::FrameLoad> asked;
  std::vector<FrameTiming> timings;
  GovernorCells cells_;
};

TEST(FramePipeline, SinksSeeEachFrameInOrderAfterItIsDrawn) {
  auto backend = platform::create_backend(platform::BackendKind::Egl);
  Renderer renderer(*backend, test::cluster_scene(), pipeline_options());
  FramePipeline pipeline(test::cluster_scene(), renderer);
  std::vector<std::string> calls;
  Recorder a("a", calls), b("b", calls);
  pipeline.add_sink(a);
  pipeline.add_sink(b);
  EXPECT_TRUE(pipeline.evaluate(speed_state(80), true, -1.0));
  const FrameRecord& first = pipeline.render(FrameRequest{0, 0.0, false, true, true, false});
  EXPECT_TRUE(first.timing.drawn);
  EXPECT_TRUE(first.link_up);
  EXPECT_EQ(first.states, &pipeline.evaluator().states());
  EXPECT_EQ(first.governor, nullptr) << "no governor, no cells";
  EXPECT_LE(first.evaluate_began_ns, first.render_began_ns);
  EXPECT_LE(first.render_began_ns, first.render_ended_ns);
  pipeline.finish();
  const std::vector<std::string> expected = {"a before 0", "b before 0", "a drawn 0", "b drawn 0",
                                             "a frame 0",  "b frame 0",  "a finish",  "b finish"};
  EXPECT_EQ(calls, expected);
  ASSERT_EQ(a.records.size(), 1u);
  EXPECT_TRUE(a.records[0].request.output);
}

// Changes are detected once, by the binding step: the same state again changes no output, the
// renderer is not dirtied, and the frame is skipped; a new state draws.
TEST(FramePipeline, AnUnchangedStateIsNotAppliedAndItsFrameIsSkipped) {
  auto backend = platform::create_backend(platform::BackendKind::Egl);
  Renderer renderer(*backend, test::cluster_scene(), pipeline_options());
  FramePipeline pipeline(test::cluster_scene(), renderer);
  EXPECT_TRUE(pipeline.evaluate(speed_state(80), true, -1.0));
  EXPECT_TRUE(pipeline.render(FrameRequest{0}).timing.drawn);
  EXPECT_FALSE(pipeline.evaluate(speed_state(80), true, -1.0));
  EXPECT_FALSE(renderer.dirty());
  EXPECT_FALSE(pipeline.render(FrameRequest{1}).timing.drawn);
  EXPECT_TRUE(pipeline.evaluate(speed_state(120), true, -1.0));
  EXPECT_TRUE(renderer.dirty());
  EXPECT_TRUE(pipeline.render(FrameRequest{2}).timing.drawn);
  EXPECT_EQ(renderer.stats().skipped, 1u);
}

// The governor is asked once per frame with the planned load, and what it chose is drawn: the
// image equals a renderer set to that quality directly.
TEST(FramePipeline, TheGovernorsChoiceOnThePlannedLoadIsDrawn) {
  auto backend = platform::create_backend(platform::BackendKind::Egl);
  Renderer renderer(*backend, test::cluster_scene(), pipeline_options()), direct(*backend, test::cluster_scene(), pipeline_options());
  BindingEvaluator direct_evaluator(test::cluster_scene());
  FramePipeline pipeline(test::cluster_scene(), renderer);
  FixedGovernor governor;
  governor::QualityChoice cheap;
  cheap.units.assign(renderer.draw_units().size(), governor::UnitLevel{});
  cheap.global.msaa = 2;  // a rung of its own: new targets, drawn in full
  governor.choice = cheap;
  pipeline.set_governor(&governor);
  pipeline.evaluate(speed_state(80), true, -1.0);
  const FrameRecord& r = pipeline.render(FrameRequest{0, 0.0, false, true, false, false});
  ASSERT_EQ(governor.asked.size(), 1u);
  EXPECT_TRUE(governor.asked[0].drawn);
  EXPECT_TRUE(governor.asked[0].read_back);
  ASSERT_EQ(governor.timings.size(), 1u);
  EXPECT_TRUE(governor.timings[0].drawn);
  EXPECT_EQ(r.governor, governor.cells());
  EXPECT_EQ(renderer.quality(), cheap);
  direct.set_quality(cheap);
  direct_evaluator.update(speed_state(80), true, -1.0);
  direct.apply(direct_evaluator.outputs());
  direct.render(false, true);
  EXPECT_TRUE(renderer.last_image().rgba == direct.last_image().rgba) << "the governor's choice was not what was drawn";
}

// Reads each frame back where a sink sees it drawn, and keeps the states it was handed.
struct ReadingSink : FrameSink {
  explicit ReadingSink(Renderer& renderer) : renderer(renderer) {}
  void on_drawn(const FrameRecord& f) override {
    images.push_back(renderer.read().rgba);
    states.push_back(*f.states);
  }
  void on_frame(const FrameRecord&) override {}
  Renderer& renderer;
  std::vector<std::vector<std::uint8_t>> images;
  std::vector<std::vector<BindingState>> states;
};

TEST(FramePipeline, OverlappedFramesReachTheSinksDrawnWithTheirOwnStates) {
  auto backend = platform::create_backend(platform::BackendKind::Egl);
  Renderer seq_renderer(*backend, test::cluster_scene(), pipeline_options());
  Renderer ovl_renderer(*backend, test::cluster_scene(), pipeline_options());
  FramePipeline sequential(test::cluster_scene(), seq_renderer), overlapped(test::cluster_scene(), ovl_renderer);
  overlapped.set_overlap(true);
  ReadingSink seq_sink(seq_renderer), ovl_sink(ovl_renderer);
  sequential.add_sink(seq_sink);
  overlapped.add_sink(ovl_sink);
  const double speeds[] = {40, 80, 80, 120, 30};  // the third unchanged: a skipped frame in flight
  for (std::uint64_t n = 0; n < std::size(speeds); ++n) {
    sequential.evaluate(speed_state(speeds[n]), true, -1.0);
    sequential.render(FrameRequest{n});
    // The next frame is evaluated and planned while this one is in flight; the one before reaches
    // the sinks only then, with the state it was drawn from.
    overlapped.evaluate(speed_state(speeds[n]), true, -1.0);
    overlapped.plan(FrameRequest{n});
    EXPECT_EQ(overlapped.complete() != nullptr, n > 0);
    EXPECT_EQ(ovl_sink.images.size(), n);
    overlapped.draw();
    EXPECT_TRUE(overlapped.in_flight());
  }
  overlapped.finish();
  EXPECT_FALSE(overlapped.in_flight());
  ASSERT_EQ(ovl_sink.images.size(), seq_sink.images.size());
  for (std::size_t n = 0; n < seq_sink.images.size(); ++n) {
    EXPECT_TRUE(ovl_sink.images[n] == seq_sink.images[n]) << "frame " << n << " differs from the sequential pipeline's";
    ASSERT_EQ(ovl_sink.states[n].size(), seq_sink.states[n].size());
    for (std::size_t b = 0; b < seq_sink.states[n].size(); ++b)
      EXPECT_EQ(ovl_sink.states[n][b].value, seq_sink.states[n][b].value) << "frame " << n << " binding " << b;
  }
  EXPECT_EQ(ovl_renderer.stats().skipped, 1u);
}

}  // namespace
