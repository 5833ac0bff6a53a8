// The two benchmarks of meter-bench, each in its own file (fidelity.cpp, accuracy.cpp).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "meter/platform/backend.hpp"

namespace meter::bench {

int run_fidelity(platform::BackendKind kind, const std::filesystem::path& out, const std::filesystem::path& doc,
                 const std::string& quality);
int run_accuracy(platform::BackendKind kind, const std::filesystem::path& out, const std::filesystem::path& doc,
                 const std::filesystem::path& model_file, int rounds, int frames, const std::vector<std::string>& only);

}  // namespace meter::bench
