// Small test scenes written with tinygltf's writer, so the tests do not depend on Blender exports.
#pragma once

#include <string>
#include <utility>

#include "meter/engine/vocabulary.hpp"

namespace meter::engine::test {

// A dial: dark unlit face, red unlit needle on node "Needle" driven by animation "SpeedNeedle"
// (value v km/h keyed at time v/24 s, angle 130 - v degrees about +Z), a lit PBR telltale quad
// "TT_ABS" (material "TT_ABS_On", emissive bound), a morphing fuel bar "FuelBar" (one target),
// text anchors "Text_Speed" and "Text_Status", a directional light and the camera "Camera".
// Writes dir/dial.gltf (buffers embedded) and returns its path.
std::string write_dial_scene(const std::string& dir);

// The matching scene config (320x160, bindings for speed, ABS, fuel, speed text, link loss).
std::string dial_config_json();

// scenes/cluster converted with its own config (groups included, optimized), once per process.
const Scene& cluster_scene();

// A fresh empty directory under the build tree for one test.
std::string scratch_dir(const std::string& name);

// A perspective camera with a vertical field of view of `yfov` radians.
inline Camera perspective_camera(std::string name, float yfov) {
  Camera c;
  c.name = std::move(name);
  c.yfov = yfov;
  return c;
}

// A unit quad (two triangles) in the XY plane with POSITION + NORMAL, centred on the origin.
inline Primitive quad_primitive(int material, float size = 1.0f) {
  Primitive p;
  p.material = material;
  p.vertex_count = 4;
  p.stride = 6;
  p.layout = {{AttributeSemantic::Position, -1, 3, 0}, {AttributeSemantic::Normal, -1, 3, 3}};
  const float h = size * 0.5f;
  p.vertices = {-h, -h, 0, 0, 0, 1, h, -h, 0, 0, 0, 1, h, h, 0, 0, 0, 1, -h, h, 0, 0, 0, 1};
  p.indices = {0, 1, 2, 0, 2, 3};
  p.bounds_min = glm::vec3(-h, -h, 0), p.bounds_max = glm::vec3(h, h, 0);
  return p;
}

}  // namespace meter::engine::test
