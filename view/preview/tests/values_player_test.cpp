// Values CSV playback: the state at each playback time, the file's duration, bad rows refused
// before playing.
#include "meter/preview/values_player.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "meter/protocol/catalog.hpp"
#include "meter/runner/view_error.hpp"

namespace meter::preview {
namespace {

using protocol::SignalStatus;
using ::testing::HasSubstr;
constexpr protocol::SignalId kSpeed = protocol::sig::kSpeed;
constexpr protocol::SignalId kLeft = protocol::sig::kTurnLeft;

const char* kDrive =
    "time,signal,value,status\n"
    "0,Vehicle.Speed,0\n"
    "# accelerating\n"
    "0.5,Vehicle.Speed,50\n"
    "1.25,Vehicle.Speed,120\n"
    "1.0,Cluster.Telltale.TurnLeft,1\n"
    "2.0,Vehicle.Speed,80,timed-out\n";

TEST(ValuesPlayer, GivesTheStateAtEachPlaybackTime) {
  ValuesPlayer p(kDrive, "drive.csv");
  EXPECT_DOUBLE_EQ(p.duration(), 2.0);
  protocol::SignalTable v;
  p.state_at(0.0, v);
  EXPECT_EQ(v.get(kSpeed).value, 0.0);
  EXPECT_EQ(v.get(kSpeed).status, SignalStatus::Valid);
  EXPECT_EQ(v.get(kLeft).status, SignalStatus::NotAvailable) << "its first row is later";
  p.state_at(0.75, v);
  EXPECT_EQ(v.get(kSpeed).value, 50.0);
  p.state_at(1.3, v);
  EXPECT_EQ(v.get(kSpeed).value, 120.0);
  EXPECT_EQ(v.get(kLeft).value, 1.0);
  p.state_at(5.0, v);
  EXPECT_EQ(v.get(kSpeed).value, 80.0);
  EXPECT_EQ(v.get(kSpeed).status, SignalStatus::TimedOut);
  // A restart goes back to the early rows.
  p.state_at(0.6, v);
  EXPECT_EQ(v.get(kSpeed).value, 50.0);
  EXPECT_EQ(v.get(kSpeed).status, SignalStatus::Valid);
}

TEST(ValuesPlayer, ABadRowIsRefusedBeforePlaying) {
  try {
    ValuesPlayer p("time,signal,value\n0,Vehicle.Speed,1\n9,Vehicle.Sped,2\n", "drive.csv");
    FAIL() << "a row naming no catalog signal was accepted";
  } catch (const runner::ViewError& e) {
    EXPECT_THAT(e.what(), HasSubstr("drive.csv:3"));
    EXPECT_THAT(e.what(), HasSubstr("Vehicle.Sped"));
  }
  EXPECT_THROW(ValuesPlayer::load("/nonexistent/drive.csv"), runner::ViewError);
}

}  // namespace
}  // namespace meter::preview
