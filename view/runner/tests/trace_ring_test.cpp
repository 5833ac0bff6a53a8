// --trace-on-overrun: the ring keeps the last seconds of slices, an overrunning frame writes them
// as a trace-event document, and a view that overruns every frame does not write every frame.
#include "meter/runner/trace_ring.hpp"

#include <fstream>
#include <sstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "scratch_files.hpp"

namespace meter::runner {
namespace {

using ::testing::HasSubstr;

protocol::TraceEvent slice(const char* name, std::int64_t begin, std::int64_t end) {
  return protocol::TraceEvent{name, "view", begin, end, 7, 1, {}};
}

TEST(TraceRing, KeepsOnlyTheEventsEndingWithinItsWindow) {
  TraceRing ring(1000, 100);
  ring.add(slice("a", 0, 100));
  ring.add(slice("b", 500, 900));
  ring.add(slice("c", 1000, 1200));  // a ends 1100 before c: out of the 1000 ns window
  const auto held = ring.events();
  ASSERT_EQ(held.size(), 2U);
  EXPECT_EQ(held[0].name, "b");
  EXPECT_EQ(held[1].name, "c");
}

TEST(TraceRing, IsBoundedByCountToo) {
  TraceRing ring(1'000'000, 3);
  for (int i = 0; i < 5; ++i) ring.add(slice("s", i, i + 1));
  const auto held = ring.events();
  ASSERT_EQ(held.size(), 3U);
  EXPECT_EQ(held.front().begin_ns, 2) << "the oldest go first";
}

TEST(TraceRing, TheDocumentIsATraceEventFileWithNames) {
  const std::string doc = trace_document("meter-view", 7, {{1, "render loop"}}, {slice("render", 1000, 3500)});
  EXPECT_THAT(doc, HasSubstr("\"traceEvents\":["));
  EXPECT_THAT(doc, HasSubstr("{\"name\":\"thread_name\",\"ph\":\"M\",\"pid\":7,\"tid\":1,\"args\":{\"name\":\"render loop\"}}"));
  EXPECT_THAT(doc, HasSubstr("{\"name\":\"render\",\"cat\":\"view\",\"ph\":\"X\",\"ts\":1.000,\"dur\":2.500,\"pid\":7,\"tid\":1}"));
  EXPECT_EQ(doc.substr(doc.size() - 4), "\n]}\n") << "closed: the file is whole when written";
}

TEST(TraceEvents, AnOverrunningFrameWritesTheRingOnceAWindow) {
  const auto dir = testing::scratch_dir();
  TraceEvents events("", 20.0, dir);  // no --trace-json file, a 20 ms threshold
  ASSERT_TRUE(events.on());
  events.thread_name(1, "render loop");
  const std::int64_t now = protocol::monotonic_now_ns();
  events.complete("render", "view", now - 30'000'000, now, 1, {{"frame", 4}});
  EXPECT_EQ(events.frame_ended(3, 19'000'000), "") << "under the threshold: nothing written";
  const std::string file = events.frame_ended(4, 30'000'000);
  ASSERT_EQ(file, (dir / "overrun_000004.json").string());
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_THAT(text.str(), HasSubstr("\"name\":\"render\""));
  EXPECT_THAT(text.str(), HasSubstr("\"args\":{\"frame\":4}"));
  EXPECT_EQ(events.frame_ended(5, 40'000'000), "") << "a second overrun within the ring's length writes no file";
  EXPECT_EQ(events.overrun_files(), 1U);
}

TEST(TraceEvents, WithoutTheOptionNothingIsKept) {
  TraceEvents events("", 0.0, testing::scratch_dir());
  EXPECT_FALSE(events.on());
  EXPECT_EQ(events.frame_ended(0, 1'000'000'000), "");
}

}  // namespace
}  // namespace meter::runner
