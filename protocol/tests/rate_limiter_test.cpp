#include <gtest/gtest.h>

#include "meter/protocol/log/rate_limiter.hpp"

using meter::protocol::RateLimiter;

TEST(RateLimiter, BurstOfFiveThenOneASecondCountingTheRest) {
  RateLimiter r;
  for (int i = 0; i < 5; ++i) EXPECT_EQ(r.admit("bad-frame", 100.0), 0u) << i;
  EXPECT_FALSE(r.admit("bad-frame", 100.0));
  EXPECT_FALSE(r.admit("bad-frame", 100.5));
  EXPECT_FALSE(r.admit("bad-frame", 100.9));
  // a second after the burst one token is back: the line carries the three left out
  EXPECT_EQ(r.admit("bad-frame", 101.0), 3u);
  EXPECT_FALSE(r.admit("bad-frame", 101.2));
  EXPECT_EQ(r.admit("bad-frame", 102.3), 1u);
}

TEST(RateLimiter, KindsHaveTheirOwnBudgetsAndRefillToTheBurstOnly) {
  RateLimiter r;
  for (int i = 0; i < 5; ++i) r.admit("a", 0.0);
  EXPECT_FALSE(r.admit("a", 0.0));
  EXPECT_EQ(r.admit("b", 0.0), 0u);
  // an hour of silence gives back 5 lines, not 3600
  for (int i = 0; i < 5; ++i) EXPECT_TRUE(r.admit("a", 3600.0)) << i;
  EXPECT_FALSE(r.admit("a", 3600.0));
  r.clear();
  EXPECT_EQ(r.admit("a", 3600.0), 0u);
}

TEST(RateLimiter, SuppressedNote) {
  EXPECT_EQ(meter::protocol::suppressed_note(0), "");
  EXPECT_EQ(meter::protocol::suppressed_note(7), " (7 similar message(s) suppressed)");
}
