#include "meter/protocol/log/logger.hpp"

#include <chrono>
#include <iostream>
#include <mutex>

#include "meter/protocol/log/log_format.hpp"

namespace meter::protocol {

namespace {

class StreamSink : public RecordSink {
 public:
  StreamSink(std::ostream& out, LogForm form, std::string program) : out_(out), form_(form), program_(std::move(program)) {}
  void write(const LogRecord& r) override {
    out_ << (form_ == LogForm::Json ? format_json(r, program_) : format_text(r)) << '\n';
    out_.flush();
  }

 private:
  std::ostream& out_;
  LogForm form_;
  std::string program_;
};

struct Logger {
  std::mutex mutex;
  LogLevel threshold = LogLevel::Info;
  std::unique_ptr<RecordSink> sink = make_stream_sink(std::cerr, LogForm::Text, "");
};

Logger& logger() {
  static Logger l;
  return l;
}

std::int64_t realtime_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

}  // namespace

std::unique_ptr<RecordSink> make_stream_sink(std::ostream& out, LogForm form, std::string program) {
  return std::make_unique<StreamSink>(out, form, std::move(program));
}

void configure_logging(std::string program, LogLevel threshold, std::unique_ptr<RecordSink> sink) {
  Logger& l = logger();
  std::lock_guard lock(l.mutex);
  l.threshold = threshold;
  l.sink = sink ? std::move(sink) : make_stream_sink(std::cerr, LogForm::Text, std::move(program));
}

LogLevel log_threshold() {
  Logger& l = logger();
  std::lock_guard lock(l.mutex);
  return l.threshold;
}

void write_log(LogRecord record) {
  Logger& l = logger();
  std::lock_guard lock(l.mutex);
  if (!level_passes(record.level, l.threshold)) return;
  if (record.time_ns == 0) record.time_ns = realtime_now_ns();
  l.sink->write(record);
}

LogLine::LogLine(std::ostream& err, LogLevel level, std::string component, std::vector<LogField> fields,
                 const char* code_file, int code_line)
    : LogLine(level, std::move(component), std::move(fields), code_file, code_line) {
  if (dynamic_cast<LogStream*>(&err) == nullptr) err_ = &err;
}

LogLine::LogLine(LogLevel level, std::string component, std::vector<LogField> fields, const char* code_file,
                 int code_line) {
  record_.level = level;
  record_.component = std::move(component);
  record_.fields = std::move(fields);
  record_.code_file = code_file;
  record_.code_line = code_line;
}

LogLine::~LogLine() {
  try {
    std::string text = std::move(text_).str();
    while (!text.empty() && text.back() == '\n') text.pop_back();
    if (err_ != nullptr) {
      *err_ << text << '\n';
      return;
    }
    split_prefix(text, record_.prefix, record_.message);
    write_log(std::move(record_));
  } catch (...) {
    // a log line never ends the program
  }
}

LogStream::LogStream(LogLevel level, std::string component)
    : std::ostream(nullptr), buffer_(level, std::move(component)) {
  rdbuf(&buffer_);
}

LogStream::~LogStream() { end_line(); }

void LogStream::end_line() {
  std::lock_guard lock(buffer_.mutex_);
  if (!buffer_.line_.empty()) buffer_.emit();
}

void LogStream::LineBuffer::emit() {
  LogRecord r;
  r.level = level_;
  r.component = component_;
  split_prefix(line_, r.prefix, r.message);
  line_.clear();
  write_log(std::move(r));
}

LogStream::LineBuffer::int_type LogStream::LineBuffer::overflow(int_type c) {
  if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
  const char ch = traits_type::to_char_type(c);
  xsputn(&ch, 1);
  return c;
}

std::streamsize LogStream::LineBuffer::xsputn(const char* s, std::streamsize n) {
  std::lock_guard lock(mutex_);
  for (std::streamsize i = 0; i < n; ++i) {
    if (s[i] == '\n') {
      emit();  // an empty line too: a blank separator stays one
    } else {
      line_ += s[i];
    }
  }
  return n;
}

int LogStream::LineBuffer::sync() { return 0; }

}  // namespace meter::protocol
