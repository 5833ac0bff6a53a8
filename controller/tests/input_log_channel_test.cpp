#include <gtest/gtest.h>

#include <stdexcept>

#include "meter/controller/input/candump_log.hpp"
#include "meter/controller/input/log_channel.hpp"

using namespace meter::controller;

TEST(LogChannel, FileHashNSelectsOneChannelOfTheLog) {
  EXPECT_EQ(parse_log_address("drive.blf#2").path, "drive.blf");
  EXPECT_EQ(parse_log_address("drive.blf#2").channel, 2);
  EXPECT_EQ(parse_log_address("drive.blf").channel, 0);
  EXPECT_EQ(parse_log_address("a#b.log").path, "a#b.log");
  EXPECT_THROW(parse_log_address("drive.blf#0"), std::invalid_argument);
  EXPECT_THROW(parse_log_address("drive.blf#256"), std::invalid_argument);

  // candump: can0 is channel 1 and vcan7 channel 2, in the order they first appear.
  const ParsedLog log = parse_candump_log("(1.0) can0 100#01\n(1.1) vcan7 200#02\n(1.2) can0 100#03\n");
  const ParsedLog two = select_log_channel(log, 2, "d.log");
  ASSERT_EQ(two.frames.size(), 1u);
  EXPECT_EQ(two.frames[0].id, 0x200u);
  EXPECT_EQ(two.frames[0].timestamp_ns, 1100000000);  // on the log's own clock
  EXPECT_EQ(select_log_channel(log, 0, "d.log").frames.size(), 3u);
  try {
    select_log_channel(log, 3, "d.log");
    FAIL() << "no frame on channel 3";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "d.log#3: no frame on channel 3 (the log's channels: 1, 2)");
  }
}
