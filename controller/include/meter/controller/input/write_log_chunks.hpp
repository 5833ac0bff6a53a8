// The loop every log writer runs: a source's frames encoded into one buffer and handed out in
// chunks, so a long log is written with a bounded buffer and its progress told as it goes.
#pragma once

#include <cstddef>
#include <functional>
#include <ostream>
#include <string>

#include "meter/controller/input/can_frame.hpp"
#include "meter/controller/input/log_format.hpp"
#include "meter/controller/input/log_source.hpp"

namespace meter::controller {

// Appends one frame's record (a text line, a BLF object) to the chunk being built.
using AppendFrameRecord = std::function<void(const CanFrame& frame, std::string& chunk)>;
// Writes out a chunk (as it is, or packed into a container); the chunk is emptied after it.
using WriteChunk = std::function<void(const std::string& chunk)>;

// A text log's chunk: 1 MiB of lines.
inline constexpr std::size_t kLogTextChunk = std::size_t{1} << 20;

// Writes each chunk to `out` as it is (a text log).
WriteChunk write_to(std::ostream& out);

// Reads `frames` to its end, appending each with `append`; each time the chunk holds at least
// `chunk_bytes`, `write` takes it and `progress` is told the frames written so far. The last,
// shorter chunk is written at the end when it holds anything. Returns the frames written.
std::size_t write_log_chunks(LogSource& frames, std::size_t chunk_bytes, const AppendFrameRecord& append,
                             const WriteChunk& write, const LogProgress& progress);

}  // namespace meter::controller
