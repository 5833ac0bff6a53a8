// Opening the view's output files (frames.csv, the timing CSV, the trace).
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

namespace meter::runner {

// `path` truncated for writing; throws ViewError "<path>: <failure>" when it cannot be.
std::ofstream create_output_file(const std::filesystem::path& path, const std::string& failure = "cannot write");

}  // namespace meter::runner
