#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "meter/protocol/signal_change.hpp"

using namespace meter::protocol;

TEST(SignalChange, TheValueBitsAndTheStatusDecide) {
  EXPECT_FALSE(signal_changed(50.0, SignalStatus::Valid, 50.0, SignalStatus::Valid));
  EXPECT_TRUE(signal_changed(50.0, SignalStatus::Valid, 50.5, SignalStatus::Valid));
  EXPECT_TRUE(signal_changed(50.0, SignalStatus::Valid, 50.0, SignalStatus::TimedOut));  // status alone
  // -0.0 and 0.0 compare equal with == but travel as different bits and print differently.
  EXPECT_TRUE(value_changed(0.0, -0.0));
  EXPECT_TRUE(value_changed(-0.0, 0.0));
  EXPECT_FALSE(value_changed(-0.0, -0.0));
  // Exact: the smallest step is a change.
  EXPECT_TRUE(value_changed(1.0, std::nextafter(1.0, 2.0)));
  // Total: a value equals itself, even one that != calls unequal to itself.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(value_changed(nan, nan));
  static_assert(!value_changed(3.0, 3.0));
}
