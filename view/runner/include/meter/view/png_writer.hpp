// Writes dumped frames as PNG on its own thread. Encoding one 640x240 PNG took 80-190 ms on the
// loaded CI host (measured with --trace), longer than a frame at 10 fps: done on the render
// thread it kept the link unserviced for that long every frame (no heartbeats, so the controller
// declared the view lost, and updates waited in the socket) and made the view miss its frame
// clock. At most kMaxPending images wait (the one being written counts); a caller that finds the
// queue full waits (every dumped frame is written), servicing whatever `while_full` does meanwhile.
// A file that cannot be written is counted and its error kept; the writer goes on with the next
// (a debugging dump must not stop the cluster): failures() tells the live loop, check() the exit.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "meter/platform/image.hpp"

namespace meter::view {

class PngWriter {
 public:
  static constexpr std::size_t kMaxPending = 3;
  // Called on the writer thread after each file is written (the latency trace's "w" row).
  using OnWritten = std::function<void(std::uint64_t frame)>;
  // Called on the writer thread just before a file is encoded (the trace's encode slice begins).
  using OnStarted = std::function<void(std::uint64_t frame)>;

  explicit PngWriter(OnWritten on_written = {}, OnStarted on_started = {});
  ~PngWriter();  // finish(), without throwing
  PngWriter(const PngWriter&) = delete;
  PngWriter& operator=(const PngWriter&) = delete;

  // Queues a copy of `image` for `file`.
  void write(const platform::Image& image, std::filesystem::path file, std::uint64_t frame,
             const std::function<void()>& while_full);
  // Writes what is queued and stops the thread. Idempotent.
  void finish();
  // Throws ViewError with the first write error, if any.
  void check();
  // Files that could not be written so far, and the first one's error ("" if none).
  std::uint64_t failures();
  std::string first_error();

 private:
  struct Job {
    platform::Image image;
    std::filesystem::path file;
    std::uint64_t frame = 0;
  };
  void rethrow();  // mutex_ held
  void run();

  OnWritten on_written_;
  OnStarted on_started_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Job> queue_;
  bool done_ = false;
  std::string error_;
  std::uint64_t failures_ = 0;
  std::thread thread_;  // last: starts once everything it uses exists
};

}  // namespace meter::view
