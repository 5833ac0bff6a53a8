// Complexity of the glTF converter: a file with 100,000 nodes converts (tinygltf, validation,
// conversion, programs) in time linear in its node count (bound and method:
// tests/support/linear_scaling.hpp).
#include <gtest/gtest.h>

#include <fstream>
#include <iostream>
#include <string>

#include "linear_scaling.hpp"
#include "meter/config/scene_config_parser.hpp"
#include "meter/convert/converter.hpp"
#include "test_scenes.hpp"

using namespace meter::convert;
using meter::test::kLinearRatioBound;
using meter::test::kScaleFactor;

namespace {

// `nodes` nodes in an 8-ary tree (depth log8 n, like an exported cluster's hierarchy), each
// translated and named; every 100th carries the one triangle mesh. Written to dir/name.gltf.
std::string write_node_tree(const std::string& dir, const std::string& name, int nodes) {
  // One triangle: three float32 VEC3 positions (0,0,0) (1,0,0) (0,1,0), base64.
  std::string json = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],)"
                     R"("buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,)"
                     R"(AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],)"
                     R"("bufferViews":[{"buffer":0,"byteLength":36}],)"
                     R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",)"
                     R"("min":[0,0,0],"max":[1,1,0]}],)"
                     R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[)";
  json.reserve(static_cast<std::size_t>(nodes) * 96);
  for (int i = 0; i < nodes; ++i) {
    if (i) json += ',';
    json += "{\"name\":\"N" + std::to_string(i) + "\",\"translation\":[0.5,0.25,0]";
    if (i % 100 == 99) json += ",\"mesh\":0";
    const int first = 8 * i + 1;
    if (first < nodes) {
      json += ",\"children\":[";
      for (int c = first; c < first + 8 && c < nodes; ++c) json += (c == first ? "" : ",") + std::to_string(c);
      json += ']';
    }
    json += '}';
  }
  json += "]}";
  const std::string path = dir + "/" + name + ".gltf";
  std::ofstream(path) << json;
  return path;
}

}  // namespace

TEST(ConvertComplexity, HundredThousandNodesConvertInLinearTime) {
  const std::string dir = meter::engine::test::scratch_dir("convert_complexity");
  const std::string large = write_node_tree(dir, "large", 100000);
  const std::string small = write_node_tree(dir, "small", 10000);
  const SceneConfig config = meter::config::parse_scene_config(R"({"format": "meter-scene-config/1"})");
  const ConvertOptions options{.optimize = false};
  ASSERT_EQ(convert_gltf(large, config, options).scene.nodes.size(), 100000u);
  const double ratio = meter::test::scaling_ratio([&] { (void)convert_gltf(small, config, options); },
                                                  [&] { (void)convert_gltf(large, config, options); });
  std::cout << "100k-node glTF: " << ratio << "x the time of a 10x smaller one\n";
  EXPECT_LT(ratio, kLinearRatioBound) << kScaleFactor << "x the nodes took " << ratio << "x the time";
}
