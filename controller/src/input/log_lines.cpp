// Text logs line by line from a stream, a 256 KiB block at a time.
#include "meter/controller/input/log_lines.hpp"

#include <string>

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

void reserve_log_frames(std::istream& in, std::size_t bytes_per_frame, std::vector<CanFrame>& frames) {
  const auto here = in.tellg();
  if (here < 0 || !in.seekg(0, std::ios::end)) return in.clear();
  const auto end = in.tellg();
  in.seekg(here);
  if (end > here) frames.reserve(static_cast<std::size_t>(end - here) / bytes_per_frame + 1);
}

void for_each_log_line(std::istream& in, const std::function<void(std::string_view)>& each_line) {
  constexpr std::size_t kBlock = 1 << 18;
  std::string buffer;
  std::size_t kept = 0;  // bytes of an unfinished line carried over from the last block
  for (;;) {
    buffer.resize(kept + kBlock);
    in.read(buffer.data() + kept, static_cast<std::streamsize>(kBlock));
    const std::size_t got = static_cast<std::size_t>(in.gcount());
    const std::size_t size = kept + got;
    buffer.resize(size);  // what was read: the unfinished line is all that moves to the front below
    const std::string_view text(buffer.data(), size);
    const std::size_t last_nl = text.rfind('\n');
    if (got == 0 || last_nl == std::string_view::npos) {
      if (got == 0) {  // the end of the file: what is left is the last line
        if (size > 0) each_line(trim_line_end(text));
        return;
      }
      kept = size;  // a line longer than a block: read on
      continue;
    }
    for_each_log_line(text.substr(0, last_nl + 1), each_line);
    kept = size - last_nl - 1;
    buffer.erase(0, last_nl + 1);
  }
}

}  // namespace meter::controller
