// Fuzzes meter-verify's frames.csv reader as meter-verify uses it: the file read back (it takes a
// path, so each input is written to a file in a private temporary folder first), then every row's
// cells read as numbers where they parse. A refusal is a VerifyError naming the file; a crash, a
// sanitizer report, another exception or a broken invariant of the rows is a finding.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "meter/verify/frames_table.hpp"

using namespace meter::verify;

namespace {

std::filesystem::path scratch_file() {
  char tmpl[] = "/tmp/meter-fuzz-frames-XXXXXX";
  const char* dir = ::mkdtemp(tmpl);
  if (dir == nullptr) std::abort();
  return std::filesystem::path(dir) / "frames.csv";
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path file = scratch_file();
  std::ofstream(file, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data),
                                                                static_cast<std::streamsize>(size));
  FramesTable t;
  try {
    t = read_frames_table(file);
  } catch (const VerifyError& e) {
    if (std::string(e.what()).rfind(file.string(), 0) != 0) std::abort();  // names the file
    return 0;
  }
  if (t.rows.empty()) std::abort();  // "no frames" is a refusal, never an empty result
  int last_line = 1;
  for (const FrameRow& r : t.rows) {
    if (r.line <= last_line || r.cells.size() > t.columns.size() || r.png.empty()) std::abort();
    if (!std::isfinite(r.time_s) || r.png.find('/') != std::string::npos) std::abort();
    last_line = r.line;
    for (const auto& column : t.columns) {
      try {
        if (!std::isfinite(number_cell(t, r, column))) std::abort();  // never a silent NaN
      } catch (const VerifyError&) {
      }
    }
  }
  return 0;
}
