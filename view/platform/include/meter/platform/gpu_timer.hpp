// GPU time of a span of GL work: GL_TIME_ELAPSED queries when the backend has them, else CPU wall
// time around glFinish() (which on llvmpipe is the same thing: rendering runs on CPU threads).
#pragma once

#include "meter/platform/backend.hpp"

#include <chrono>

namespace meter::platform {

class GpuTimer {
 public:
  explicit GpuTimer(const GpuBackend& backend);
  ~GpuTimer();
  GpuTimer(const GpuTimer&) = delete;
  GpuTimer& operator=(const GpuTimer&) = delete;

  // Starts timing GL work submitted from now on. Must alternate with stop().
  void start();
  // Ends the span and waits for the result; returns milliseconds of GPU time.
  // Throws std::logic_error when called without start().
  double stop();
  // True when GL_TIME_ELAPSED queries are used, false for the glFinish fallback.
  bool uses_queries() const { return query_ != 0; }

 private:
  const Gl* gl_ = nullptr;
  GLuint query_ = 0;
  bool running_ = false;
  std::chrono::steady_clock::time_point cpu_start_;
};

}  // namespace meter::platform
