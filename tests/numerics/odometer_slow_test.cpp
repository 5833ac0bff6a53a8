// The 1,000,000 km odometer case (label `slow`: 3.6e8 steps take tens of seconds
// under ASan; signals_numerics_test.cpp keeps a proportional 10,000 km case in `unit`).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

#include "odometer_drive.hpp"

// The full case (label `slow`): 3.6e8 steps of 10 ms at ~1000 km/h = 1,000,000 km.
// Bound: drift under 1 m against the exact sum; the integer odometer achieves 0 um.
TEST(OdometerSlow, OneMillionKmIn10msStepsDriftUnderOneMetre) {
  const auto r = meter::numerics::drive(360'000'000, 100'000);
  EXPECT_LT(std::llabs(r.odo_um - r.exact_um), 1'000'000);
  EXPECT_EQ(r.odo_um, r.exact_um);
  EXPECT_NEAR(static_cast<double>(r.exact_um) / 1e9, 1'000'000.0, 10.0);
  std::printf("1,000,000 km: integer odometer error %lld um; naive double-km accumulator error %.3f m\n",
              static_cast<long long>(r.odo_um - r.exact_um), (r.naive_km - static_cast<double>(r.exact_um) / 1e9) * 1000.0);
}

