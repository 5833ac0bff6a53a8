// A bounded buffer between two pipeline stages (CUBE's double buffers, of any depth) that measures
// its own waits: how long producers waited for space and consumers waited for an item, so a stage's
// "waiting for output" and "waiting for input" times come from the buffer it waits on. Thread-safe;
// one or more producers and consumers. A full queue either refuses the item (try_push: the caller
// counts it as dropped) or makes the producer wait (push), optionally doing other work meanwhile.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <stdexcept>

namespace meter::runner {

struct QueueCounts {
  std::uint64_t pushed = 0, popped = 0, dropped = 0;
  std::int64_t push_wait_ns = 0;  // producers waiting for space
  std::int64_t pop_wait_ns = 0;   // consumers waiting for an item
  std::size_t high_water = 0;     // most items held at once
};

template <class T>
class BoundedQueue {
 public:
  using Clock = std::chrono::steady_clock;

  // capacity >= 1 (std::invalid_argument otherwise).
  explicit BoundedQueue(std::size_t capacity) : capacity_(capacity) {
    if (capacity == 0) throw std::invalid_argument("BoundedQueue: capacity must be at least 1");
  }
  BoundedQueue(const BoundedQueue&) = delete;
  BoundedQueue& operator=(const BoundedQueue&) = delete;

  std::size_t capacity() const { return capacity_; }

  // Never waits: false when full or closed; a full queue counts the item as dropped.
  bool try_push(T&& item) {
    {
      std::lock_guard lock(mutex_);
      if (closed_) return false;
      if (occupied() >= capacity_) {
        ++counts_.dropped;
        return false;
      }
      store(std::move(item));
    }
    not_empty_.notify_one();
    return true;
  }

  // Waits while full; false when the queue is (or gets) closed. With `while_full`, the producer
  // calls it (outside the lock) instead of sleeping, until there is space: it must return within
  // a few milliseconds (e.g. a link poll with a short timeout). The whole wait is push wait.
  bool push(T&& item, const std::function<void()>& while_full = {}) {
    const auto began = Clock::now();
    bool waited = false;
    std::unique_lock lock(mutex_);
    while (!closed_ && occupied() >= capacity_) {
      waited = true;
      if (while_full) {
        lock.unlock();
        while_full();
        lock.lock();
      } else {
        not_full_.wait(lock);
      }
    }
    if (waited) counts_.push_wait_ns += elapsed_ns(began);
    if (closed_) return false;
    store(std::move(item));
    lock.unlock();
    not_empty_.notify_one();
    return true;
  }

  // Waits for an item; nullopt once the queue is closed and empty. With `hold`, the item keeps its
  // slot until release(): the bound then counts the item being worked on (an image being encoded
  // is memory held like a queued one).
  std::optional<T> pop(bool hold = false) {
    const auto began = Clock::now();
    std::unique_lock lock(mutex_);
    if (items_.empty() && !closed_) {
      not_empty_.wait(lock, [&] { return closed_ || !items_.empty(); });
      counts_.pop_wait_ns += elapsed_ns(began);
    }
    if (items_.empty()) return std::nullopt;
    std::optional<T> item(std::move(items_.front()));
    items_.pop_front();
    ++counts_.popped;
    if (hold) {
      ++held_;
      return item;
    }
    lock.unlock();
    not_full_.notify_one();
    return item;
  }

  // Frees the slot of an item taken with pop(true).
  void release() {
    {
      std::lock_guard lock(mutex_);
      if (held_ == 0) throw std::logic_error("BoundedQueue::release without a held item");
      --held_;
    }
    not_full_.notify_one();
  }

  // No more pushes; consumers drain what is queued, then pop() returns nullopt. Idempotent.
  void close() {
    {
      std::lock_guard lock(mutex_);
      closed_ = true;
    }
    not_empty_.notify_all();
    not_full_.notify_all();
  }

  // Items queued plus items held.
  std::size_t size() const {
    std::lock_guard lock(mutex_);
    return occupied();
  }
  QueueCounts counts() const {
    std::lock_guard lock(mutex_);
    return counts_;
  }

 private:
  static std::int64_t elapsed_ns(Clock::time_point began) {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - began).count();
  }
  std::size_t occupied() const { return items_.size() + held_; }  // mutex_ held
  void store(T&& item) {  // mutex_ held, space checked
    items_.push_back(std::move(item));
    ++counts_.pushed;
    if (occupied() > counts_.high_water) counts_.high_water = occupied();
  }

  const std::size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable not_empty_, not_full_;
  std::deque<T> items_;
  std::size_t held_ = 0;
  bool closed_ = false;
  QueueCounts counts_;
};

}  // namespace meter::runner
