#include "output_file.hpp"

#include "meter/view/view_error.hpp"

namespace meter::view {

std::ofstream create_output_file(const std::filesystem::path& path, const std::string& failure) {
  std::ofstream out(path);
  if (!out) throw ViewError(path.string() + ": " + failure);
  return out;
}

}  // namespace meter::view
