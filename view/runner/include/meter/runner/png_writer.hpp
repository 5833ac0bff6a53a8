// Writes dumped frames as PNG on its own thread. Encoding one 640x240 PNG took 80-190 ms on the
// loaded CI host (measured with --trace), longer than a frame at 10 fps: done on the render
// thread it kept the link unserviced for that long every frame (no heartbeats, so the controller
// declared the view lost, and updates waited in the socket) and made the view miss its frame
// clock. At most kMaxPending images wait (the one being written counts); a caller that finds the
// queue full waits (every dumped frame is written), servicing whatever `while_full` does meanwhile,
// or, offered a frame with DumpOverflow::Drop, the frame is not queued and counted as dropped (a
// slow encoder then never holds the render loop back).
// The writer thread is the live pipeline's output stage: each frame's rows are put top-down (the
// "check" stage of --stats, where a check of the read-back pixels would sit) and then PNG encode
// and write. Both stages' busy and input-wait times are kept for --stats.
// A file that cannot be written is counted and its error kept; the writer goes on with the next
// (a debugging dump must not stop the cluster): failures() tells the live loop, check() the exit.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "meter/platform/image.hpp"
#include "meter/runner/bounded_queue.hpp"
#include "meter/runner/readback_frame.hpp"
#include "meter/runner/stage_meter.hpp"

namespace meter::runner {

// --dump-policy: what a dump does when the writer's queue is full.
enum class DumpOverflow { Drop, Block };

class PngWriter {
 public:
  static constexpr std::size_t kMaxPending = 3;
  static constexpr int kLane = 2;  // the writer thread, for the stage meters
  // Called on the writer thread after each file is written (the latency trace's "w" row).
  using OnWritten = std::function<void(std::uint64_t frame)>;
  // Called on the writer thread just before a file is encoded (the trace's encode slice begins).
  using OnStarted = std::function<void(std::uint64_t frame)>;

  explicit PngWriter(OnWritten on_written = {}, OnStarted on_started = {});
  ~PngWriter();  // finish(), without throwing
  PngWriter(const PngWriter&) = delete;
  PngWriter& operator=(const PngWriter&) = delete;

  // Queues a copy of `image` (rows top-down) for `file`, waiting while the queue is full.
  void write(const platform::Image& image, std::filesystem::path file, std::uint64_t frame,
             const std::function<void()>& while_full);
  // Queues a read-back frame (`bottom_up`: rows as GL reads them). Block waits like write(); Drop
  // returns false at once when the queue is full (the frame is counted in dropped()).
  bool offer(ReadbackFrame&& frame, bool bottom_up, DumpOverflow overflow, const std::function<void()>& while_full);
  // Writes what is queued and stops the thread. Idempotent.
  void finish();
  // Throws ViewError with the first write (or check) error, if any.
  void check();
  // Files that could not be written so far, and the first one's error ("" if none).
  std::uint64_t failures();
  std::string first_error();
  std::uint64_t dropped() const { return queue_.counts().dropped; }
  QueueCounts queue_counts() const { return queue_.counts(); }
  const StageMeter& check_meter() const { return check_meter_; }
  // Test only (--inject-slow-stage check): slept in the check stage of every frame. Set before the first frame.
  void slow_check(std::chrono::nanoseconds delay) { check_delay_ = delay; }
  const StageMeter& encode_meter() const { return encode_meter_; }

 private:
  struct Job {
    ReadbackFrame frame;
    bool bottom_up = false;
  };
  void rethrow();  // mutex_ held
  void run();
  void handle(Job& job);

  OnWritten on_written_;
  OnStarted on_started_;
  StageMeter check_meter_{"check", kLane};
  std::chrono::nanoseconds check_delay_{0};
  StageMeter encode_meter_{"encode", kLane};
  BoundedQueue<Job> queue_{kMaxPending};
  std::mutex mutex_;  // error_, failures_
  std::string error_;
  std::uint64_t failures_ = 0;
  std::thread thread_;  // last: starts once everything it uses exists
};

}  // namespace meter::runner
