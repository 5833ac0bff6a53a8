// Internal helpers shared by the generator, the uber shader and the optimizer.
#pragma once

#include "meter/shadergen/shadergen.hpp"

namespace meter::shadergen::detail {

bool any_material_texture(const MaterialFeatures& f);
bool per_pixel_normal(ShadingModel m);
int attribute_count(const MaterialFeatures& f);
// Throws std::invalid_argument naming the offending field.
void validate(const MaterialFeatures& f);

}  // namespace meter::shadergen::detail
