#include "fixed_vehicle.hpp"

#include <string>

namespace meter::controller::fuzz {

const Database& demo_dbc() {
  static const Database db = load_dbc(std::string(METER_SOURCE_DIR) + "/controller/vehicles/demo/demo.dbc");
  return db;
}

const Mapping& demo_mapping() {
  static const Mapping map = load_mapping(std::string(METER_SOURCE_DIR) + "/controller/vehicles/demo/demo.map");
  return map;
}

}  // namespace meter::controller::fuzz
