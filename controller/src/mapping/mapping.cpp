// A mapping's look-ups.
#include "meter/controller/mapping/mapping.hpp"

namespace meter::controller {

const OutputMapping* Mapping::find(protocol::SignalId id) const {
  for (auto& o : outputs)
    if (o.id == id) return &o;
  return nullptr;
}

}  // namespace meter::controller
