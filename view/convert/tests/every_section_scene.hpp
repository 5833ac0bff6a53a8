// A hand-built scene that fills every section and record of the scene package (every kind of
// field at a value other than its default where it can), for the package's writer / reader tests.
#pragma once

#include "meter/convert/vocabulary.hpp"

namespace meter::convert::test {

Scene every_section();

}  // namespace meter::convert::test
