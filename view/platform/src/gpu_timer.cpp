#include "meter/platform/gpu_timer.hpp"

#include <stdexcept>

namespace meter::platform {

GpuTimer::GpuTimer(const GpuBackend& backend) : gl_(&backend.gl()) {
  if (gl_->info.has_timer_query) gl_->GenQueries(1, &query_);
}

GpuTimer::~GpuTimer() {
  if (query_) gl_->DeleteQueries(1, &query_);
}

void GpuTimer::start() {
  if (running_) throw std::logic_error("GpuTimer::start called twice without stop");
  running_ = true;
  if (query_) {
    gl_->BeginQuery(GL_TIME_ELAPSED, query_);
  } else {
    // Without queries the only GPU boundary we can observe is "all earlier work finished".
    gl_->Finish();
    cpu_start_ = std::chrono::steady_clock::now();
  }
}

double GpuTimer::stop() {
  if (!running_) throw std::logic_error("GpuTimer::stop called without start");
  running_ = false;
  if (query_) {
    gl_->EndQuery(GL_TIME_ELAPSED);
    GLuint64 ns = 0;
    gl_->GetQueryObjectui64v(query_, GL_QUERY_RESULT, &ns);  // blocks until available
    return static_cast<double>(ns) / 1e6;
  }
  gl_->Finish();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - cpu_start_).count();
}

}  // namespace meter::platform
