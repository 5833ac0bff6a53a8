// Recorded CAN log formats behind one small interface, and the one list of them. A format knows
// its files (by their first bytes, else by their extension), reads a file from a stream a frame at
// a time (a LogSource), and may write one from a source; `run` (every log:FILE input), `decode` and
// `convert-log` open logs only through open_log_source(), so a new format is its own file plus one
// entry in log_formats().
#pragma once

#include <cstddef>
#include <functional>
#include <istream>
#include <memory>
#include <ostream>
#include <span>
#include <string>
#include <string_view>

#include "meter/controller/input/log_source.hpp"
#include "meter/controller/input/parsed_log.hpp"

namespace meter::controller {

// Told how many frames are written so far, now and then, while a long log is written.
using LogProgress = std::function<void(std::size_t frames_written)>;

struct LogFormat {
  std::string_view name;         // "candump": in messages and the help text
  std::string_view example;      // the start of such a file, for the message when no format fits
  std::span<const std::string_view> extensions;  // ".log": claims files whose start no format knows
  // True when the start of a file (up to kLogSniffBytes of it) is in this format.
  bool (*sniff)(std::string_view head);
  // The file from its first byte as a source of its frames in file order, read a record at a time
  // as they are asked for, with every record that breaks the grammar and the records of other kinds
  // passed over. The source reads `in`, which must outlive it.
  std::unique_ptr<LogSource> (*open)(std::istream& in);
  // Writes the source's frames (read to its end) as a file of this format and returns how many;
  // nullptr: this build reads the format only.
  std::size_t (*write)(LogSource& frames, std::ostream& out, const LogProgress& progress) = nullptr;
};

// How much of a file the formats' sniff() sees.
inline constexpr std::size_t kLogSniffBytes = 4096;

// Every format this build reads, in the order they are asked.
std::span<const LogFormat> log_formats();

// The format of a file that starts with `head`: the first whose sniff() accepts it; when none does
// (a damaged first page), the first that claims the path's extension; nullptr when neither.
const LogFormat* find_log_format(std::string_view path, std::string_view head);
// The format that writes files named like `path` (its extension); nullptr when none does.
const LogFormat* find_log_writer(std::string_view path);

// Opens a log in its format as a source, read up to its first frame (of `channel`, 1..255; 0: any).
// Throws std::runtime_error naming the file when it cannot be read; when no format fits (with the
// first non-blank line and its number, the formats known and their extensions); when not one of
// its records gives a frame (with its first bad records, file:line and what was expected there);
// and when no frame is on the channel asked (with the channels the log holds).
std::unique_ptr<LogSource> open_log_source(const std::string& path, int channel = 0);


// A text log's line without the spaces, tabs and carriage return at its end (blank lines are not
// errors in any text format).
std::string_view trim_line_end(std::string_view line);

// "candump, asc, blf, trc" (the names of log_formats(), comma separated)
std::string log_format_names();

}  // namespace meter::controller
