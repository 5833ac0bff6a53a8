// Skins: joint lists and inverse bind matrices (affine, at most shadergen::kMaxSkinJoints joints).
#include "convert_context.hpp"
#include "meter/shadergen/shadergen.hpp"

namespace meter::convert {

void validate_skin(ConvertContext& ctx, std::size_t si) {
  const auto& skin = ctx.m.skins[si];
  const std::string p = idx("skins", si);
  if (skin.joints.empty()) ctx.error(p + ".joints", "a skin needs at least one joint");
  if (skin.joints.size() > std::size_t(shadergen::kMaxSkinJoints)) {
    ctx.error(p + ".joints", std::to_string(skin.joints.size()) + " joints; at most " + std::to_string(shadergen::kMaxSkinJoints) + " are supported");
  }
  for (std::size_t k = 0; k < skin.joints.size(); ++k) {
    if (skin.joints[k] < 0 || static_cast<std::size_t>(skin.joints[k]) >= ctx.m.nodes.size()) ctx.error(p + idx(".joints", k), "node index out of range");
  }
  if (skin.inverseBindMatrices >= 0) {
    if (auto* d = ctx.use_accessor(skin.inverseBindMatrices, p + ".inverseBindMatrices", {TINYGLTF_TYPE_MAT4}, {TINYGLTF_COMPONENT_TYPE_FLOAT})) {
      if (d->size() / 16 < skin.joints.size()) ctx.error(p + ".inverseBindMatrices", "fewer matrices than joints");
      for (std::size_t mtx = 0; mtx < d->size() / 16; ++mtx) {
        for (int r = 0; r < 4; ++r) {
          const double v = (*d)[mtx * 16 + std::size_t(r) * 4 + 3];
          const double want = r == 3 ? 1.0 : 0.0;
          if (v != want) {
            ctx.error(p + ".inverseBindMatrices", "matrix " + std::to_string(mtx) + " element " + std::to_string(r * 4 + 3) + " is " + fmt(v) +
                                                  " (the last row of an affine matrix must be 0 0 0 1)");
          }
        }
      }
    }
  }
}


void convert_skins(const ConvertContext& ctx, Scene& s) {
  for (std::size_t i = 0; i < ctx.m.skins.size(); ++i) {
    const auto& k = ctx.m.skins[i];
    Skin out;
    out.name = k.name;
    out.joints = k.joints;
    for (std::size_t j = 0; j < k.joints.size(); ++j) {
      glm::mat4 m(1.0f);
      if (k.inverseBindMatrices >= 0) {
        const auto& d = ctx.accessor_values[static_cast<std::size_t>(k.inverseBindMatrices)];
        for (int c = 0; c < 16; ++c) m[c / 4][c % 4] = static_cast<float>(d[j * 16 + std::size_t(c)]);
      }
      out.inverse_bind.push_back(m);
    }
    s.skins.push_back(std::move(out));
  }
}

}  // namespace meter::convert
