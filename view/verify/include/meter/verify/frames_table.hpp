// A run folder's frames.csv as meter-view writes it (meter/runner/frames_csv.hpp), read back for
// meter-verify: one row per dumped PNG with the bound signals as drawn.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace meter::verify {

// Every bad input: the message names the file, the line, the column and what was expected.
struct VerifyError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct FrameRow {
  int line = 0;  // in frames.csv (the header is line 1)
  std::uint64_t frame = 0;
  double time_s = 0.0;
  std::string png;
  bool link_up = true, drawn = true;
  std::map<std::string, std::string> cells;  // column name -> cell (unquoted)
};

struct FramesTable {
  std::filesystem::path file;
  std::vector<std::string> columns;
  std::vector<FrameRow> rows;
  bool has(const std::string& column) const;
};

// Splits one CSV line (RFC 4180 quotes, "" inside quotes). Throws VerifyError naming `where` on
// an unterminated quote.
std::vector<std::string> split_csv_line(const std::string& line, const std::string& where);

// Reads frames.csv: the five frame columns must exist, every row must have as many cells as the
// header and parse (frame an integer, time a number, link_up and drawn 0 or 1, png a file name).
FramesTable read_frames_table(const std::filesystem::path& file);

// A cell as a number; throws VerifyError naming the row's line and the column.
double number_cell(const FramesTable& t, const FrameRow& row, const std::string& column);

}  // namespace meter::verify
