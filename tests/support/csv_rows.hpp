// Reading what meter-view writes while it runs (frames.csv, timing.csv): rows of a CSV with a
// header, and waiting for a live view's first dumped frame.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "process.hpp"

namespace meter::testing {

// Rows of a CSV with a header, as column name -> cell; a row shorter than the header (still being
// written) is left out.
std::vector<std::map<std::string, std::string>> read_csv(const std::filesystem::path& file);

// Waits until the live view has dumped its first frame (frames.csv has a row): its loop is running.
// Fails the calling test (gtest fatal failure) if the view ends first or nothing comes in 30 s.
void wait_for_first_dump(const std::filesystem::path& frames_csv, ChildProcess& view);

}  // namespace meter::testing
