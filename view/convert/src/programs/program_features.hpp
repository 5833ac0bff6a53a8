// The pieces of program generation that are pure functions of the converted Scene (private to
// meter_convert): the shader generator's feature set of one draw, and the scene constants the
// shader optimizer folds into a program.
#pragma once

#include <vector>

#include "meter/convert/scene.hpp"
#include "meter/shadergen/shadergen.hpp"

namespace meter::convert {

// The features of the program drawing `prim` of `node` (before shadergen::canonical): what the
// material uses that the vertex layout can feed. `vertex_alpha` for mesh concatenation members.
shadergen::MaterialFeatures draw_features(const Scene& s, const Node& node, const Primitive& prim,
                                          const shadergen::LightCounts& lights, bool vertex_alpha);

// How many lights of each type `light_nodes` (light nodes in light_order) hold: what every
// program of the scene evaluates.
shadergen::LightCounts count_lights(const Scene& s, const std::vector<int>& light_nodes);

// Nodes whose world transform can change at runtime (animated themselves or below an animated node).
std::vector<char> dynamic_nodes(const Scene& s);

// Values the scene never changes, folded into the program by shadergen::optimize(): the material
// factors (unless a binding animates the material), ambient, exposure, environment, texture
// transforms, and the lights (position and direction only for lights that cannot move).
// `light_nodes` in light_order.
shadergen::ConstantValues folding_constants(const Scene& s, const Material& m, bool fold_material,
                                            const std::vector<int>& light_nodes, const std::vector<char>& dyn);

}  // namespace meter::convert
