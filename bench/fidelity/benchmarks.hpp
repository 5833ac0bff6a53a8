// The benchmarks of meter-bench, each in its own file (fidelity.cpp, accuracy.cpp, film_emulation.cpp).
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
int run_film(platform::BackendKind kind, const std::filesystem::path& out, const std::vector<std::string>& only, int passes,
             int converged_passes);

}  // namespace meter::bench
