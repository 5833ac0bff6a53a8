// Text logs line by line from a stream, a 256 KiB block at a time.
#include "meter/controller/input/log_lines.hpp"

#include <cstring>

#include "meter/controller/input/log_format.hpp"

namespace meter::controller {

void for_each_log_line(std::string_view text, const std::function<void(std::string_view)>& each_line) {
  std::size_t pos = 0;
  while (pos < text.size()) {
    const std::size_t nl = text.find('\n', pos);
    const std::size_t end = nl == std::string_view::npos ? text.size() : nl;
    each_line(trim_line_end(text.substr(pos, end - pos)));
    pos = end + 1;
  }
}

bool LogLineCursor::next(std::string_view& line) {
  constexpr std::size_t kBlock = 1 << 18;
  for (;;) {
    const char* start = buffer_.data() + pos_;
    const std::size_t left = buffer_.size() - pos_;
    if (const void* nl = std::memchr(start, '\n', left)) {
      const std::size_t n = static_cast<std::size_t>(static_cast<const char*>(nl) - start);
      line = trim_line_end(std::string_view(start, n));
      pos_ += n + 1;
      return true;
    }
    if (eof_) {  // the end of the file: what is left is the last line
      if (left == 0) return false;
      line = trim_line_end(std::string_view(start, left));
      pos_ = buffer_.size();
      return true;
    }
    // Only the unfinished line moves to the front; a line longer than a block reads on.
    buffer_.erase(0, pos_);
    pos_ = 0;
    const std::size_t kept = buffer_.size();
    buffer_.resize(kept + kBlock);
    in_.read(buffer_.data() + kept, static_cast<std::streamsize>(kBlock));
    const auto got = static_cast<std::size_t>(in_.gcount());
    buffer_.resize(kept + got);
    if (got == 0) eof_ = true;
  }
}

}  // namespace meter::controller
