// The pieces of program generation that are pure functions of the converted Scene (private to
// meter_convert): the shader generator's feature set of one draw, and the scene constants the
// shader optimizer folds into a program.
#pragma once

#include <vector>

#include "meter/convert/vocabulary.hpp"
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

// The program features of draw `d` under another shading model / precision (`stored`: its
// program's features). Texture and light features are derived again from the material and the
// primitive (as the converter does), because a cheaper model dropped them from the stored features:
// going back up must restore them. Everything else (vertex alpha, skin, morphs, alpha mode) is kept.
shadergen::MaterialFeatures features_at(const Scene& s, const DrawItem& d, const shadergen::MaterialFeatures& stored,
                                        shadergen::ShadingModel shading, shadergen::Precision precision);

// A PBR material shown with a Blinn-Phong-style model keeps the converter's defaults (specular 0.5,
// shininess 32) unless mapped: the usual conversion is alpha = roughness^2, shininess = 2/alpha^2 - 2
// (same highlight width), specular = F0 (0.04 for dielectrics, base colour for metals), diffuse =
// the PBR diffuse colour, base colour x (1 - metallic) (black for metals: a chrome part lit as a
// white Lambert surface plus its reflection would be blown out).
struct PhongParameters {
  glm::vec3 specular_color{0.5f};
  float shininess = 32.0f;
  float base_scale = 1.0f;
};
PhongParameters pbr_as_phong(const Material& m);

}  // namespace meter::convert
