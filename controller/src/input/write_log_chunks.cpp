#include "meter/controller/input/write_log_chunks.hpp"

namespace meter::controller {

WriteChunk write_to(std::ostream& out) {
  return [&out](const std::string& chunk) { out.write(chunk.data(), static_cast<std::streamsize>(chunk.size())); };
}

std::size_t write_log_chunks(LogSource& frames, std::size_t chunk_bytes, const AppendFrameRecord& append,
                             const WriteChunk& write, const LogProgress& progress) {
  std::string chunk;
  std::size_t written = 0;
  while (const CanFrame* f = frames.next()) {
    append(*f, chunk);
    ++written;
    if (chunk.size() >= chunk_bytes) {
      write(chunk);
      chunk.clear();
      progress(written);
    }
  }
  if (!chunk.empty()) write(chunk);
  return written;
}

}  // namespace meter::controller
