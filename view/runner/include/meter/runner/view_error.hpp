// The error every part of the view process throws for a bad option, input file or output: the
// message names the file (and line) or the flag and what was expected. meter-view prints it as
// "meter-view: error: <message>" and exits 1.
#pragma once

#include <stdexcept>

namespace meter::runner {

class ViewError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace meter::runner
