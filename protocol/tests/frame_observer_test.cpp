// Subscriber::set_frame_observer: what meter-linkdump sees is every frame the view's end of the
// link receives, in order, before it is applied, and each reads back equal from its recording line.
#include <gtest/gtest.h>

#include <variant>
#include <vector>

#include "meter/protocol/recording.hpp"
#include "test_util.hpp"

using namespace meter::protocol;
using test::pump;
using namespace std::chrono_literals;

namespace {
LinkOptions quick(std::string name) {
  LinkOptions o = link_options(std::move(name), 300ms);  // heartbeats every 100 ms, loss after 300
  o.reconnect_min = 5ms;
  return o;
}
}  // namespace

TEST(FrameObserver, SeesEveryReceivedFrameInOrder) {
  test::TempDir dir;
  Publisher pub(dir.unix_endpoint(), quick("ctl"));
  pub.set(sig::kSpeed, 88.0, SignalStatus::Valid);
  Subscriber sub(dir.unix_endpoint(), quick("view"));
  std::vector<Frame> seen;
  sub.set_frame_observer([&](const Frame& f) {
    // Before it is applied: the first SNAPSHOT arrives while the state is still the initial one.
    if (std::holds_alternative<Snapshot>(f.message) && seen.size() == 1) {
      EXPECT_EQ(sub.get(sig::kSpeed).status, SignalStatus::NotAvailable);
    }
    seen.push_back(f);
  });
  ASSERT_TRUE(pump(pub, sub, [&] { return sub.link_up(); }));
  pub.set(sig::kSpeed, 90.5, SignalStatus::TimedOut);
  ASSERT_TRUE(pump(pub, sub, [&] { return sub.get(sig::kSpeed).value == 90.5; }));

  ASSERT_GE(seen.size(), 3u);
  EXPECT_EQ(seen.size(), sub.stats().messages_received);
  ASSERT_TRUE(std::holds_alternative<Hello>(seen[0].message));
  EXPECT_EQ(std::get<Hello>(seen[0].message).name, "ctl");
  ASSERT_TRUE(std::holds_alternative<Snapshot>(seen[1].message));
  const auto& last = seen.back();
  ASSERT_TRUE(std::holds_alternative<Delta>(last.message)) << format_line({0, last});
  const auto& d = std::get<Delta>(last.message);
  ASSERT_EQ(d.signals.size(), 1u);
  EXPECT_EQ(d.signals[0].id, sig::kSpeed);
  EXPECT_EQ(d.signals[0].status, SignalStatus::TimedOut);
  for (std::size_t i = 0; i < seen.size(); ++i) {
    const RecordedFrame r{static_cast<std::int64_t>(i), seen[i]};
    const auto back = parse_line(format_line(r), "live", i + 1);
    EXPECT_EQ(back.frame.sequence, seen[i].sequence);
    EXPECT_EQ(back.frame.timestamp_ns, seen[i].timestamp_ns);
    EXPECT_TRUE(back.frame.message == seen[i].message) << format_line(r);
  }
}
