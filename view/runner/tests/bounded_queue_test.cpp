// The bounded buffer between pipeline stages: its bound, drops, waits measured on both sides,
// closing, and held items counting against the bound.
#include "meter/runner/bounded_queue.hpp"

#include <future>
#include <thread>

#include <gtest/gtest.h>

namespace meter::runner {
namespace {

using std::chrono::milliseconds;

TEST(BoundedQueue, AFullQueueRefusesTryPushAndCountsTheDrop) {
  BoundedQueue<int> q(2);
  EXPECT_TRUE(q.try_push(1));
  EXPECT_TRUE(q.try_push(2));
  EXPECT_FALSE(q.try_push(3)) << "full: refused at once";
  EXPECT_EQ(q.size(), 2U);
  const auto c = q.counts();
  EXPECT_EQ(c.pushed, 2U);
  EXPECT_EQ(c.dropped, 1U);
  EXPECT_EQ(c.high_water, 2U);
  EXPECT_EQ(q.pop(), 1) << "first in, first out";
  EXPECT_EQ(q.pop(), 2);
}

TEST(BoundedQueue, CapacityZeroIsRefused) { EXPECT_THROW(BoundedQueue<int>(0), std::invalid_argument); }

TEST(BoundedQueue, PushWaitsForSpaceDoingTheCallersWorkAndMeasuresTheWait) {
  BoundedQueue<int> q(1);
  ASSERT_TRUE(q.push(1));
  EXPECT_EQ(q.counts().push_wait_ns, 0) << "space at once: no wait";
  int calls = 0;
  auto consumer = std::async(std::launch::async, [&] {
    std::this_thread::sleep_for(milliseconds(30));
    return q.pop();
  });
  EXPECT_TRUE(q.push(2, [&] {
    ++calls;
    std::this_thread::sleep_for(milliseconds(1));
  }));
  EXPECT_EQ(consumer.get(), 1);
  EXPECT_GE(calls, 1) << "the producer serviced its own work while it waited";
  // The consumer slept 30 ms before taking the item; the producer waited at least most of it
  // (20 ms: the consumer thread may start up to a few ms after the push began).
  EXPECT_GE(q.counts().push_wait_ns, 20'000'000);
  EXPECT_EQ(q.counts().dropped, 0U) << "a waiting push drops nothing";
  EXPECT_EQ(q.pop(), 2);
}

TEST(BoundedQueue, PopWaitsForAnItemAndMeasuresTheWait) {
  BoundedQueue<int> q(4);
  auto producer = std::async(std::launch::async, [&] {
    std::this_thread::sleep_for(milliseconds(30));
    q.push(7);
  });
  EXPECT_EQ(q.pop(), 7);
  producer.get();
  EXPECT_GE(q.counts().pop_wait_ns, 20'000'000) << "as above: 30 ms slept, 20 ms at least seen";
}

TEST(BoundedQueue, CloseLetsConsumersDrainThenEnds) {
  BoundedQueue<int> q(4);
  q.push(1);
  q.push(2);
  q.close();
  EXPECT_FALSE(q.push(3)) << "no pushes after close";
  EXPECT_FALSE(q.try_push(3));
  EXPECT_EQ(q.counts().dropped, 0U) << "refused after close is not a drop";
  EXPECT_EQ(q.pop(), 1);
  EXPECT_EQ(q.pop(), 2);
  EXPECT_EQ(q.pop(), std::nullopt);
}

TEST(BoundedQueue, CloseWakesAWaitingProducerAndConsumer) {
  BoundedQueue<int> full(1);
  full.push(1);
  auto producer = std::async(std::launch::async, [&] { return full.push(2); });
  BoundedQueue<int> empty(1);
  auto consumer = std::async(std::launch::async, [&] { return empty.pop(); });
  std::this_thread::sleep_for(milliseconds(10));
  full.close();
  empty.close();
  EXPECT_FALSE(producer.get());
  EXPECT_EQ(consumer.get(), std::nullopt);
}

TEST(BoundedQueue, AHeldItemKeepsItsSlotUntilReleased) {
  BoundedQueue<int> q(2);
  q.push(1);
  q.push(2);
  ASSERT_EQ(q.pop(true), 1);
  EXPECT_EQ(q.size(), 2U) << "the held item still counts";
  EXPECT_FALSE(q.try_push(3)) << "so the queue is still full";
  q.release();
  EXPECT_TRUE(q.try_push(3));
  EXPECT_THROW(q.release(), std::logic_error) << "nothing held";
}

}  // namespace
}  // namespace meter::runner
