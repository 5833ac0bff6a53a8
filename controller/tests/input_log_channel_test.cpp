#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

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
  const std::string path = std::filesystem::temp_directory_path() / ("meter-channel-" + std::to_string(::getpid()) + ".log");
  std::ofstream(path) << "(1.0) can0 100#01\n(1.1) vcan7 200#02\n(1.2) can0 100#03\n";
  const ParsedLog two = read_whole_log(*open_log_input(path + "#2"));
  ASSERT_EQ(two.frames.size(), 1u);
  EXPECT_EQ(two.frames[0].id, 0x200u);
  EXPECT_EQ(two.frames[0].timestamp_ns, 1100000000);  // on the log's own clock
  EXPECT_EQ(read_whole_log(*open_log_input(path)).frames.size(), 3u);
  try {
    open_log_input(path + "#3");
    FAIL() << "no frame on channel 3";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), path + "#3: no frame on channel 3 (the log's channels: 1, 2)");
  }
  std::filesystem::remove(path);
}
