// Complexity of the scene-config parser: a config whose bindings nest five levels deep parses in
// time linear in its size (bound and method: tests/support/linear_scaling.hpp).
#include <gtest/gtest.h>

#include <iostream>
#include <string>

#include "linear_scaling.hpp"
#include "meter/config/scene_config_parser.hpp"

using namespace meter::bridge;
using meter::test::kLinearRatioBound;
using meter::test::kScaleFactor;

namespace {

// `bindings` text, colour and animation bindings and as many groups. Depth five: the config
// object, its "bindings" array, a binding object, its "map"/"failsafe"/"color" member, that
// member's values; and the config, "groups", a group, its "members", the member names.
std::string generated_config(int bindings) {
  std::string json = R"({"format": "meter-scene-config/1", "size": [1280, 480], "bindings": [)";
  for (int i = 0; i < bindings; ++i) {
    const std::string n = std::to_string(i);
    if (i) json += ',';
    switch (i % 3) {
      case 0:
        json += R"({"signal": "Vehicle.Powertrain.Transmission.CurrentGear", "kind": "text", "node": "T)" + n +
                R"(", "format": "%.0f", "color": [1, 0.5, 0.25, 1], "map": {"-1": "R", "0": "N", "126": "P", "127": "D"},)"
                R"( "failsafe": {"text": "-"}})";
        break;
      case 1:
        json += R"({"signal": "Vehicle.Speed", "kind": "color", "material": "M)" + n +
                R"(", "off": [0, 0, 0, 1], "on": [1, 0.2, 0.1, 1], "input": [0, 260], "failsafe": {"value": 0}})";
        break;
      default:
        json += R"({"signal": "Vehicle.Speed", "kind": "animation", "animation": "A)" + n +
                R"(", "input": [0, 260], "time": [0, 10.8], "smoothing_ms": 80, "failsafe": {"value": 0}})";
    }
  }
  json += R"(], "groups": [)";
  for (int i = 0; i < bindings; ++i) {
    const std::string n = std::to_string(i);
    json += (i ? "," : "") + std::string(R"({"name": "G)") + n + R"(", "members": ["A)" + n + R"(", "B)" + n + R"("]})";
  }
  return json + "]}";
}

}  // namespace

TEST(SceneConfigComplexity, DeepConfigParsesInLinearTime) {
  const std::string large = generated_config(20000);
  const std::string small = generated_config(2000);
  ASSERT_EQ(meter::config::parse_scene_config(large).bindings.size(), 20000u);
  const double ratio = meter::test::scaling_ratio([&] { (void)meter::config::parse_scene_config(small); },
                                                  [&] { (void)meter::config::parse_scene_config(large); });
  std::cout << "5-level config: " << ratio << "x the time of a 10x smaller one\n";
  EXPECT_LT(ratio, kLinearRatioBound) << kScaleFactor << "x the config took " << ratio << "x the time";
}
