// Internal helpers shared by the generator, the uber shader and the optimizer.
#pragma once

#include "meter/shadergen/shadergen.hpp"

namespace meter::shadergen::detail {

bool has_texture(const MaterialFeatures& f, TextureSlot slot);
bool uses_texcoord1(const MaterialFeatures& f, TextureSlot slot);
bool any_material_texture(const MaterialFeatures& f);
bool is_lit(ShadingModel m);
bool per_pixel_normal(ShadingModel m);
int attribute_count(const MaterialFeatures& f);
// Throws std::invalid_argument naming the offending field.
void validate(const MaterialFeatures& f);

}  // namespace meter::shadergen::detail
