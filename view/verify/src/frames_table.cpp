#include "meter/verify/frames_table.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>

namespace meter::verify {
namespace {

std::string at_line(const std::filesystem::path& file, int line) { return file.string() + ":" + std::to_string(line); }

bool parse_double(const std::string& s, double* out) {
  if (s.empty()) return false;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s.c_str(), &end);
  if (errno != 0 || end != s.c_str() + s.size() || !std::isfinite(v)) return false;
  *out = v;
  return true;
}

}  // namespace

bool FramesTable::has(const std::string& column) const {
  return std::find(columns.begin(), columns.end(), column) != columns.end();
}

std::vector<std::string> split_csv_line(const std::string& line, const std::string& where) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') cells.back() += '"', ++i;
      else if (c == '"') quoted = false;
      else cells.back() += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      cells.emplace_back();
    } else if (c != '\r') {
      cells.back() += c;
    }
  }
  if (quoted) throw VerifyError(where + ": unterminated quoted cell");
  return cells;
}

FramesTable read_frames_table(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw VerifyError(file.string() + ": cannot open (a run folder holds frames.csv and the PNGs meter-view dumped)");
  FramesTable t;
  t.file = file;
  std::string line;
  if (!std::getline(in, line)) throw VerifyError(file.string() + ":1: empty file, expected the frames.csv header");
  t.columns = split_csv_line(line, at_line(file, 1));
  for (const char* c : {"frame", "time_s", "png", "link_up", "drawn"}) {
    if (!t.has(c)) throw VerifyError(at_line(file, 1) + ": no column \"" + c + "\" (not a meter-view frames.csv)");
  }
  int n = 1;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty() || line == "\r") continue;
    const auto cells = split_csv_line(line, at_line(file, n));
    if (cells.size() != t.columns.size()) {
      throw VerifyError(at_line(file, n) + ": " + std::to_string(cells.size()) + " cells, the header has " +
                        std::to_string(t.columns.size()));
    }
    FrameRow r;
    r.line = n;
    for (std::size_t i = 0; i < cells.size(); ++i) r.cells[t.columns[i]] = cells[i];
    double frame = 0;
    // Up to 2^53 a double holds every whole number; beyond, it is no frame counter (and beyond
    // 2^64 converting it would be undefined).
    if (!parse_double(r.cells["frame"], &frame) || frame < 0 || frame != std::floor(frame) || frame > 9007199254740992.0) {
      throw VerifyError(at_line(file, n) + ": column frame: \"" + r.cells["frame"] + "\" is not a frame number");
    }
    r.frame = static_cast<std::uint64_t>(frame);
    r.time_s = number_cell(t, r, "time_s");
    for (const char* c : {"link_up", "drawn"}) {
      const auto& v = r.cells[c];
      if (v != "0" && v != "1") throw VerifyError(at_line(file, n) + ": column " + c + ": \"" + v + "\", expected 0 or 1");
    }
    r.link_up = r.cells["link_up"] == "1", r.drawn = r.cells["drawn"] == "1";
    r.png = r.cells["png"];
    if (r.png.empty() || r.png.find('/') != std::string::npos) {
      throw VerifyError(at_line(file, n) + ": column png: \"" + r.png + "\", expected a file name in the run folder");
    }
    t.rows.push_back(std::move(r));
  }
  if (t.rows.empty()) throw VerifyError(file.string() + ": no frames (only the header)");
  return t;
}

double number_cell(const FramesTable& t, const FrameRow& row, const std::string& column) {
  const auto it = row.cells.find(column);
  if (it == row.cells.end()) throw VerifyError(at_line(t.file, 1) + ": no column \"" + column + "\"");
  double v = 0;
  if (!parse_double(it->second, &v)) {
    throw VerifyError(at_line(t.file, row.line) + ": column " + column + ": \"" + it->second + "\" is not a number");
  }
  return v;
}

}  // namespace meter::verify
