// The two ways editors save a file, for the preview's tests; scratch folders are the runner tests'.
#pragma once

#include <filesystem>
#include <string>

#include "../../runner/tests/scratch_files.hpp"

namespace meter::preview::testing {

using runner::testing::scratch_dir;

// Writes in place (truncate + write + close), as a plain editor does.
inline void save_in_place(const std::filesystem::path& file, const std::string& text) {
  runner::testing::write_text(file, text);
}

// Writes a temporary file beside `file` and renames it over `file`, as most editors and Blender's
// exporter save: the file's inode changes.
inline void save_by_rename(const std::filesystem::path& file, const std::string& text) {
  const auto tmp = file.parent_path() / ("." + file.filename().string() + ".tmp");
  save_in_place(tmp, text);
  std::filesystem::rename(tmp, file);
}

}  // namespace meter::preview::testing
