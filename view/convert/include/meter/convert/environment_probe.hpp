// The world's reflection probe as EEVEE (Blender 3.x) builds it, baked offline from the
// equirectangular environment image: a cube map whose level L is the world filtered by a GGX lobe
// of alpha (L / (levels - 1))^4 (bridge::EnvironmentProbe). Pure: an image in, texels out.
#pragma once

#include <glm/glm.hpp>

#include "meter/bridge/scene.hpp"
#include "meter/platform/image.hpp"

namespace meter::convert {

// EEVEE's default world probe size (Render Properties > Indirect Lighting > Cubemap Size, "512",
// the value every scene build script sets).
inline constexpr int kEnvironmentProbeFaceSize = 512;

// Bakes `equirect` (sRGB, Blender's equirectangular mapping, docs/engine.md "Environment") into a
// probe with faces of `face_size` texels (a power of two, 8..4096; std::invalid_argument
// otherwise, or for an image under 2 x 2). Level 0 is the image resampled; each further level
// integrates EEVEE's sample counts (32, 40, 64, then 128) of the GGX lobe around the texel's
// direction (N = V = R), each sample read from the image's mip level whose texel covers the
// sample's share of the lobe (GPU Gems 3, ch. 20, eq. 13).
bridge::EnvironmentProbe bake_environment_probe(const platform::Image& equirect, int face_size);

// The unit direction (glTF axes) through the centre of texel (x, y) of cube face `face` (0..5 =
// +X, -X, +Y, -Y, +Z, -Z) of a face `size` texels wide: GL's cube-map convention, so a runtime
// cube-map lookup in that direction reads that texel.
glm::vec3 cube_texel_direction(int face, int x, int y, int size);

}  // namespace meter::convert
