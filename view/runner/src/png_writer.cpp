#include "meter/runner/png_writer.hpp"

#include <thread>

#include "meter/platform/flip_rows.hpp"
#include "meter/runner/view_error.hpp"

namespace meter::runner {

PngWriter::PngWriter(OnWritten on_written, OnStarted on_started)
    : on_written_(std::move(on_written)),
      on_started_(std::move(on_started)),
      thread_([this] { run(); }) {}

PngWriter::~PngWriter() { finish(); }

void PngWriter::write(const platform::Image& image, std::filesystem::path file, std::uint64_t frame,
                      const std::function<void()>& while_full) {
  ReadbackFrame f;
  f.info.frame = frame;
  f.info.png = std::move(file);
  f.image = image;
  offer(std::move(f), false, DumpOverflow::Block, while_full);
}

bool PngWriter::offer(ReadbackFrame&& frame, bool bottom_up, DumpOverflow overflow,
                      const std::function<void()>& while_full) {
  Job job{std::move(frame), bottom_up};
  if (overflow == DumpOverflow::Drop) return queue_.try_push(std::move(job));
  return queue_.push(std::move(job), while_full);
}

void PngWriter::finish() {
  queue_.close();
  if (thread_.joinable()) thread_.join();
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
    const auto began = std::chrono::steady_clock::now();
    auto job = queue_.pop(true);  // held: the queue bound counts the image being written
    check_meter_.waited_input(ns_since(began));
    if (!job) return;
    try {
      handle(*job);
    } catch (const std::exception& e) {
      std::lock_guard lock(mutex_);
      if (error_.empty()) error_ = e.what();
      ++failures_;
    }
    queue_.release();
  }
}

void PngWriter::handle(Job& job) {
  const FrameInfo& info = job.frame.info;
  {
    BusyScope busy(check_meter_);
    if (check_delay_.count() > 0) std::this_thread::sleep_for(check_delay_);
    if (job.bottom_up) platform::flip_rows(job.frame.image);
  }
  if (info.png.empty()) return;
  BusyScope busy(encode_meter_);
  if (on_started_) on_started_(info.frame);
  platform::write_png(job.frame.image, info.png);
  if (on_written_) on_written_(info.frame);
}

}  // namespace meter::runner
