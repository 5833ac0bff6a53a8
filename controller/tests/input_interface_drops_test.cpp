// The interface drop counter: a sysfs counter's text parsed strictly, and the count since opening
// read from a file laid out as /sys/class/net/IFACE/statistics/rx_dropped is.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "meter/controller/input/interface_drops.hpp"

namespace meter::controller {
namespace {

namespace fs = std::filesystem;

TEST(InterfaceCounter, ParsesTheKernelsTextAndNothingElse) {
  EXPECT_EQ(parse_interface_counter("0\n"), 0U);
  EXPECT_EQ(parse_interface_counter("1635\n"), 1635U);
  EXPECT_EQ(parse_interface_counter("18446744073709551615\n"), 18446744073709551615ULL);
  EXPECT_EQ(parse_interface_counter("18446744073709551616\n"), std::nullopt) << "past 64 bits";
  EXPECT_EQ(parse_interface_counter(""), std::nullopt);
  EXPECT_EQ(parse_interface_counter("\n"), std::nullopt);
  EXPECT_EQ(parse_interface_counter("-1\n"), std::nullopt);
  EXPECT_EQ(parse_interface_counter("+5\n"), std::nullopt);
  EXPECT_EQ(parse_interface_counter("12a\n"), std::nullopt);
  EXPECT_EQ(parse_interface_counter("1 2\n"), std::nullopt);
}

class InterfaceDropsFile : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("meter_interface_drops_" + std::to_string(::getpid()));
    fs::create_directories(root_ / "vcan0" / "statistics");
  }
  void TearDown() override { fs::remove_all(root_); }
  void write(const std::string& text) { std::ofstream(root_ / "vcan0" / "statistics" / "rx_dropped") << text; }
  fs::path root_;
};

TEST_F(InterfaceDropsFile, CountsFromWhenItWasOpened) {
  write("40\n");
  InterfaceDrops drops("vcan0", root_.string());
  ASSERT_TRUE(drops.available());
  EXPECT_EQ(drops.read(), 0U) << "drops before the controller opened the bus are not its losses";
  write("47\n");
  EXPECT_EQ(drops.read(), 7U);
  write("1675\n");
  EXPECT_EQ(drops.read(), 1635U);
}

TEST_F(InterfaceDropsFile, ABadReadingKeepsTheCountReached) {
  write("10\n");
  InterfaceDrops drops("vcan0", root_.string());
  write("15\n");
  EXPECT_EQ(drops.read(), 5U);
  write("garbage\n");
  EXPECT_EQ(drops.read(), 5U) << "text that is not a counter";
  write("");
  EXPECT_EQ(drops.read(), 5U) << "an empty read";
  write("3\n");
  EXPECT_EQ(drops.read(), 5U) << "a counter below the start (the interface recreated): no negative count";
  write("12\n");
  EXPECT_EQ(drops.read(), 5U) << "nor a smaller one";
  write("30\n");
  EXPECT_EQ(drops.read(), 20U);
}

TEST_F(InterfaceDropsFile, AnInterfaceWithoutTheCounterCountsNothing) {
  InterfaceDrops missing("vcan9", root_.string());
  EXPECT_FALSE(missing.available());
  EXPECT_EQ(missing.read(), 0U);
  write("not a number\n");
  InterfaceDrops unreadable("vcan0", root_.string());
  EXPECT_FALSE(unreadable.available()) << "a start that is not a counter gives no baseline";
  EXPECT_EQ(unreadable.read(), 0U);
}

}  // namespace
}  // namespace meter::controller
