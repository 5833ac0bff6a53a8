// Scratch folders and the two ways editors save a file, for the preview's tests.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

namespace meter::preview::testing {

// An empty folder named for the running test.
inline std::filesystem::path fresh_folder() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const auto dir = std::filesystem::path(::testing::TempDir()) / "meter_preview" /
                   (std::string(info->test_suite_name()) + "." + info->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// Writes in place (truncate + write + close), as a plain editor does.
inline void save_in_place(const std::filesystem::path& file, const std::string& text) {
  std::ofstream(file, std::ios::binary | std::ios::trunc) << text;
}

// Writes a temporary file beside `file` and renames it over `file`, as most editors and Blender's
// exporter save: the file's inode changes.
inline void save_by_rename(const std::filesystem::path& file, const std::string& text) {
  const auto tmp = file.parent_path() / ("." + file.filename().string() + ".tmp");
  save_in_place(tmp, text);
  std::filesystem::rename(tmp, file);
}

}  // namespace meter::preview::testing
