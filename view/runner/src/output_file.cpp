#include "output_file.hpp"

#include "meter/runner/view_error.hpp"

namespace meter::runner {

std::ofstream create_output_file(const std::filesystem::path& path, const std::string& failure) {
  std::ofstream out(path);
  if (!out) throw ViewError(path.string() + ": " + failure);
  return out;
}

}  // namespace meter::runner
