// The lines of a text log, read from a stream a block at a time (a long log is never held whole
// in memory), and a text format's log source: its line reader fed one line at a time, when the
// replay asks for the next frame.
#pragma once

#include <functional>
#include <istream>
#include <string>
#include <string_view>

#include "meter/controller/input/log_source.hpp"
#include "meter/controller/input/parsed_log.hpp"

namespace meter::controller {

// The lines of `in` in order, each without '\n' and without the spaces, tabs and carriage return
// at its end (trim_line_end); blank lines are handed over too.
class LogLineCursor {
 public:
  explicit LogLineCursor(std::istream& in) : in_(in) {}
  // The next line; false at the end of the stream. The line stays valid until the next call.
  bool next(std::string_view& line);

 private:
  std::istream& in_;
  std::string buffer_;
  std::size_t pos_ = 0;  // the start of the next line in buffer_
  bool eof_ = false;
};

// Calls each_line(line) for every line of text already in memory (a file's head), trimmed alike.
void for_each_log_line(std::string_view text, const std::function<void(std::string_view)>& each_line);

// A text log through a line reader (a class built on the window it fills, a `ParsedLog&`, with
// `void line(std::string_view)`), a line at a time.
template <class LineReader>
class TextLogSource : public LogSource {
 public:
  explicit TextLogSource(std::istream& in) : lines_(in), reader_(window()) { watch(in); }

 private:
  LogLineCursor lines_;
  LineReader reader_;
  // Lines up to the next frame or bad line (blank lines, comments and headers give neither).
  bool read_more() override {
    const std::size_t frames = window().frames.size(), bad = window().bad_lines.size();
    std::string_view line;
    while (window().frames.size() == frames && window().bad_lines.size() == bad) {
      if (!lines_.next(line)) return false;
      reader_.line(line);
    }
    return true;
  }
};

}  // namespace meter::controller
