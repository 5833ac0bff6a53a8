#include "meter/view/png_writer.hpp"

#include "meter/view/view_error.hpp"

namespace meter::view {

PngWriter::PngWriter(OnWritten on_written, OnStarted on_started)
    : on_written_(std::move(on_written)), on_started_(std::move(on_started)), thread_([this] { run(); }) {}

PngWriter::~PngWriter() { finish(); }

void PngWriter::write(const platform::Image& image, std::filesystem::path file, std::uint64_t frame,
                      const std::function<void()>& while_full) {
  for (;;) {
    {
      std::lock_guard lock(mutex_);
      if (queue_.size() < kMaxPending) {
        queue_.push_back(Job{image, std::move(file), frame});
        break;
      }
    }
    while_full();
  }
  wake_.notify_one();
}

void PngWriter::finish() {
  {
    std::lock_guard lock(mutex_);
    if (done_) return;
    done_ = true;
  }
  wake_.notify_one();
  thread_.join();
}

void PngWriter::check() {
  std::lock_guard lock(mutex_);
  rethrow();
}

std::uint64_t PngWriter::failures() {
  std::lock_guard lock(mutex_);
  return failures_;
}

std::string PngWriter::first_error() {
  std::lock_guard lock(mutex_);
  return error_;
}

void PngWriter::rethrow() {
  if (!error_.empty()) throw ViewError(error_);
}

void PngWriter::run() {
  for (;;) {
    Job job;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return done_ || !queue_.empty(); });
      if (queue_.empty()) return;
      job = std::move(queue_.front());
    }
    try {
      if (on_started_) on_started_(job.frame);
      platform::write_png(job.image, job.file);
      if (on_written_) on_written_(job.frame);
    } catch (const std::exception& e) {
      std::lock_guard lock(mutex_);
      if (error_.empty()) error_ = e.what();
      ++failures_;
    }
    std::lock_guard lock(mutex_);
    queue_.pop_front();  // only now: the queue bound counts the image being written
  }
}

}  // namespace meter::view
