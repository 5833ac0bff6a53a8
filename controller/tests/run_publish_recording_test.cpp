// --record: what the controller publishes, as a link recording on the input's clock. The file reads
// back with the recording parser (the same lines meter-linkdump writes), stamped with the times
// given, and STATUS lines appear only when the fault flags change.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "../src/run/publish_recording.hpp"
#include "meter/protocol/catalog.hpp"
#include "meter/protocol/recording.hpp"

namespace meter::controller {
namespace {

TEST(PublishRecording, ReadsBackOnTheGivenClock) {
  const auto file = std::filesystem::temp_directory_path() / "meter_publish_recording_test.rec";
  const protocol::SignalId speed = protocol::find_signal("Vehicle.Speed")->id;
  {
    PublishRecording rec(file.string());
    ASSERT_TRUE(rec.on());
    rec.snapshot(1'000'000'000, {protocol::SignalUpdate{speed, protocol::SignalStatus::Valid, 0.0, false, {}}});
    rec.status(1'000'000'000, 5, 0, 0);
    rec.delta(1'010'000'000, {protocol::SignalUpdate{speed, protocol::SignalStatus::Valid, 12.5, false, {}}});
    rec.delta(1'020'000'000, {});        // a tick that changed nothing writes nothing
    rec.status(1'020'000'000, 9, 0, 0);  // same flags: not written
    rec.status(1'030'000'000, 9, 0, 4);
    rec.close();
  }
  std::ifstream in(file);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, protocol::recording_header(protocol::catalog_hash()));
  in.seekg(0);
  const auto frames = protocol::parse_recording(in, file.string());
  ASSERT_EQ(frames.size(), 4u);
  EXPECT_TRUE(std::holds_alternative<protocol::Snapshot>(frames[0].frame.message));
  EXPECT_TRUE(std::holds_alternative<protocol::Status>(frames[1].frame.message));
  const auto& delta = std::get<protocol::Delta>(frames[2].frame.message);
  EXPECT_EQ(delta.signals.at(0).value, 12.5);
  EXPECT_EQ(frames[2].frame.timestamp_ns, 1'010'000'000);
  EXPECT_EQ(frames[2].received_ns, 1'010'000'000);
  EXPECT_EQ(std::get<protocol::Status>(frames[3].frame.message).fault_flags, 4u);
  EXPECT_EQ(frames[3].frame.timestamp_ns, 1'030'000'000);
  for (std::size_t i = 0; i < frames.size(); ++i) EXPECT_EQ(frames[i].frame.sequence, i + 1);
  std::filesystem::remove(file);
}

TEST(PublishRecording, AnUnwritablePathIsNamed) {
  try {
    PublishRecording rec("/nonexistent-dir/x.rec");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "/nonexistent-dir/x.rec: cannot write the recording (--record)");
  }
  PublishRecording off("");
  EXPECT_FALSE(off.on());
  off.delta(1, {protocol::SignalUpdate{}});  // off: nothing happens
  off.close();
}

}  // namespace
}  // namespace meter::controller
