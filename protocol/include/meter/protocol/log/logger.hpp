// The process's logger: a level threshold and one sink (plain text or JSON on stderr, the journal,
// DLT), set once by main from --log / --log-level; every record of the process goes through it.
// Without configure_logging the sink is plain text on stderr at level info: today's output.
#pragma once

#include <memory>
#include <mutex>
#include <ostream>
#include <sstream>
#include <streambuf>
#include <string>
#include <vector>

#include "meter/protocol/log/log_record.hpp"

namespace meter::protocol {

// One destination for records (one small interface per backend).
class RecordSink {
 public:
  virtual ~RecordSink() = default;
  virtual void write(const LogRecord& record) = 0;
};

// Plain text (format_text) or JSON lines (format_json) on a stream, one line per record.
enum class LogForm { Text, Json };
std::unique_ptr<RecordSink> make_stream_sink(std::ostream& out, LogForm form, std::string program);

// Replaces the process's sink and threshold (thread-safe); the program names the records.
void configure_logging(std::string program, LogLevel threshold, std::unique_ptr<RecordSink> sink);
LogLevel log_threshold();
// Stamps the time if unset, filters by the threshold and hands the record to the sink.
void write_log(LogRecord record);

// Builds one record with << and writes it when it goes out of scope:
//   LogLine(err, LogLevel::Warning, "health", {log_field("input", name)}) << "meter-controller: " << ...;
// To a LogStream (main's stderr) it is a record with its level, component and fields; to any other
// stream (a test's ostringstream) it is the same text line as before, so the wording stays one.
// The record's code file and line are the call site's: __builtin_FILE and __builtin_LINE as default
// arguments take the caller's (GCC and clang alike; std::source_location needs a clang newer than the
// sanitizer build's 14).
class LogLine {
 public:
  LogLine(std::ostream& err, LogLevel level, std::string component, std::vector<LogField> fields = {},
          const char* code_file = __builtin_FILE(), int code_line = __builtin_LINE());
  // Straight to the process's logger (code that has no `err` stream: the link, the package reader).
  LogLine(LogLevel level, std::string component, std::vector<LogField> fields = {},
          const char* code_file = __builtin_FILE(), int code_line = __builtin_LINE());
  ~LogLine();
  LogLine(const LogLine&) = delete;
  LogLine& operator=(const LogLine&) = delete;
  template <class T>
  LogLine& operator<<(const T& v) {
    text_ << v;
    return *this;
  }

 private:
  std::ostream* err_ = nullptr;  // none: the logger
  LogRecord record_;
  std::ostringstream text_;
};

// A std::ostream whose every line becomes a record (level and component given here; a leading
// "meter-...: " becomes the record's prefix): main hands it to the code that writes to `err`.
class LogStream : public std::ostream {
 public:
  LogStream(LogLevel level, std::string component);
  ~LogStream() override;
  // A line written without its newline becomes a record now (the destructor does the same).
  void end_line();

 private:
  class LineBuffer : public std::streambuf {
   public:
    LineBuffer(LogLevel level, std::string component) : level_(level), component_(std::move(component)) {}
    void emit();  // with mutex_ held
    LogLevel level_;
    std::string component_;
    std::string line_;
    std::mutex mutex_;  // threads writing at once get whole records, never a torn buffer

   protected:
    int_type overflow(int_type c) override;
    std::streamsize xsputn(const char* s, std::streamsize n) override;
    int sync() override;
  };
  LineBuffer buffer_;
  friend class LogLine;
};

}  // namespace meter::protocol
