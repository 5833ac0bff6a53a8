// Steps the integration tests that run the real processes share: convert a scene, follow a live
// view's frames.csv, read CSVs with a header. Errors are std::runtime_error with the child's log.
#pragma once

#include <chrono>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "process.hpp"

namespace meter::testing {

// Rows of a CSV with a header, as column name -> cell; a row shorter than the header (still being
// written) is left out. Cells are split at every comma (no quoted cells).
std::vector<std::map<std::string, std::string>> read_csv(const std::filesystem::path& file);

// scenes/minimal-gauge converted into `msp` by meter-convert (its log beside it).
void convert_minimal_gauge(const std::filesystem::path& msp);

// Waits until the live view has dumped its first frame (frames.csv has a row): its loop is running.
void wait_for_first_dump(const std::filesystem::path& frames_csv, ChildProcess& view,
                         std::chrono::seconds timeout = std::chrono::seconds(30));

}  // namespace meter::testing
