#include "meter/protocol/trace_events.hpp"

#include <time.h>
#include <unistd.h>

#include <cstdio>
#include <stdexcept>

namespace meter::protocol {

std::int64_t monotonic_now_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000LL + ts.tv_nsec;
}

std::int64_t realtime_now_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000LL + ts.tv_nsec;
}

std::int64_t monotonic_ns(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
}

namespace {

// Nanoseconds as microseconds with 3 decimals: exact, and a plain JSON number.
std::string micros(std::int64_t ns) {
  const bool negative = ns < 0;
  const std::uint64_t m = negative ? ~static_cast<std::uint64_t>(ns) + 1 : static_cast<std::uint64_t>(ns);
  char b[40];
  std::snprintf(b, sizeof b, "%s%llu.%03llu", negative ? "-" : "", static_cast<unsigned long long>(m / 1000),
                static_cast<unsigned long long>(m % 1000));
  return b;
}

}  // namespace

std::string json_quoted(std::string_view text) {
  std::string out = "\"";
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (byte < 0x20) {
      char b[8];
      std::snprintf(b, sizeof b, "\\u%04x", byte);
      out += b;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string format_trace_event(const TraceEvent& e) {
  std::string out = "{\"name\":" + json_quoted(e.name) + ",\"cat\":" + json_quoted(e.category) +
                    ",\"ph\":\"X\",\"ts\":" + micros(e.begin_ns) + ",\"dur\":" +
                    micros(e.end_ns > e.begin_ns ? e.end_ns - e.begin_ns : 0) + ",\"pid\":" + std::to_string(e.pid) +
                    ",\"tid\":" + std::to_string(e.tid);
  if (!e.args.empty()) {
    out += ",\"args\":{";
    for (std::size_t i = 0; i < e.args.size(); ++i) {
      out += (i ? "," : "") + json_quoted(e.args[i].first) + ":" + std::to_string(e.args[i].second);
    }
    out += "}";
  }
  return out + "}";
}

std::string format_trace_name(std::string_view kind, int pid, int tid, std::string_view name) {
  return "{\"name\":" + json_quoted(kind) + ",\"ph\":\"M\",\"pid\":" + std::to_string(pid) +
         ",\"tid\":" + std::to_string(tid) + ",\"args\":{\"name\":" + json_quoted(name) + "}}";
}

TraceEventFile::TraceEventFile(const std::string& path, std::string_view process_name) {
  if (path.empty()) return;
  buffer_.resize(1 << 20);  // the loops must not wait for a disk: write in large blocks
  out_.rdbuf()->pubsetbuf(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
  out_.open(path);
  if (!out_) throw std::runtime_error(path + ": cannot write the trace");
  on_ = true;
  pid_ = static_cast<int>(::getpid());
  out_ << "{\"displayTimeUnit\":\"ms\",\"otherData\":{\"clock\":\"CLOCK_MONOTONIC\"},\"traceEvents\":[\n";
  append(format_trace_name("process_name", pid_, 0, process_name));
}

TraceEventFile::~TraceEventFile() { close(); }

void TraceEventFile::append(const std::string& object) {
  if (!first_) out_ << ",\n";
  first_ = false;
  out_ << object;
}

void TraceEventFile::thread_name(int tid, std::string_view name) {
  if (!on_) return;
  std::lock_guard lock(mutex_);
  if (out_.is_open()) append(format_trace_name("thread_name", pid_, tid, name));
}

void TraceEventFile::complete(std::string_view name, std::string_view category, std::int64_t begin_ns,
                              std::int64_t end_ns, int tid, std::vector<std::pair<std::string, std::int64_t>> args) {
  if (!on_) return;
  std::lock_guard lock(mutex_);
  if (!out_.is_open()) return;
  append(format_trace_event(TraceEvent{std::string(name), std::string(category), begin_ns, end_ns, pid_, tid,
                                       std::move(args)}));
}

bool TraceEventFile::close() {
  if (!on_) return true;
  std::lock_guard lock(mutex_);
  if (!out_.is_open()) return true;
  out_ << "\n]}\n";
  out_.close();
  return static_cast<bool>(out_);
}

}  // namespace meter::protocol
