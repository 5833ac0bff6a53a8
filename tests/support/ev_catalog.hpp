// The shipped signal catalog plus one signal it does not have: a traction battery's displayed
// state of charge (VSS Vehicle.Powertrain.TractionBattery.StateOfCharge.Displayed), as the VSS
// JSON a user would write. Shared by the catalog unit tests and the end-to-end catalog test.
// Header-only (nlohmann/json): protocol tests use it without the test-support library.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "meter/protocol/catalog.hpp"

namespace meter::testing {

inline constexpr const char* kSocName = "Vehicle.Powertrain.TractionBattery.StateOfCharge.Displayed";
inline constexpr protocol::SignalId kSocId = 100;

// The default catalog's JSON with the TractionBattery branch added under Vehicle.Powertrain.
inline nlohmann::json ev_catalog_json() {
  auto doc = nlohmann::json::parse(protocol::default_catalog()->text());
  doc["Vehicle"]["children"]["Powertrain"]["children"]["TractionBattery"] = {
      {"type", "branch"},
      {"description", "Battery Management data."},
      {"children",
       {{"StateOfCharge",
         {{"type", "branch"},
          {"description", "Information on the state of charge of the vehicle's high voltage battery."},
          {"children",
           {{"Displayed",
             {{"type", "sensor"}, {"datatype", "float"}, {"unit", "percent"}, {"min", 0}, {"max", 100},
              {"description", "Displayed state of charge of the high voltage battery."}, {"meter_id", kSocId}}}}}}}}}};
  return doc;
}

}  // namespace meter::testing
