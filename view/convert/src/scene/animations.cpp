// Animations: samplers (key times strictly increasing, outputs sized for their interpolation,
// unit rotation keys) and channels, converted to float samplers shared per (sampler, width).
#include <cmath>
#include <map>

#include "convert_context.hpp"

namespace meter::convert {

void validate_animation(ConvertContext& ctx, std::size_t ai) {
  const auto& anim = ctx.m.animations[ai];
  const std::string p = idx("animations", ai);
  for (std::size_t si = 0; si < anim.samplers.size(); ++si) {
    const auto& s = anim.samplers[si];
    const std::string sp = p + idx(".samplers", si);
    if (s.interpolation != "LINEAR" && s.interpolation != "STEP" && s.interpolation != "CUBICSPLINE" && !s.interpolation.empty()) {
      ctx.error(sp + ".interpolation", "unknown interpolation \"" + s.interpolation + "\"");
    }
    auto* in = ctx.use_accessor(s.input, sp + ".input", {TINYGLTF_TYPE_SCALAR}, {TINYGLTF_COMPONENT_TYPE_FLOAT});
    ctx.use_accessor(s.output, sp + ".output", {TINYGLTF_TYPE_SCALAR, TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4}, {});
    if (!in) continue;
    for (std::size_t k = 0; k < in->size(); ++k) {
      if ((*in)[k] < 0) ctx.error(sp + ".input", "key " + std::to_string(k) + " has negative time " + fmt((*in)[k]));
      if (k > 0 && !((*in)[k] > (*in)[k - 1])) {
        ctx.error(sp + ".input", "key " + std::to_string(k) + " time " + fmt((*in)[k]) + " is not greater than the previous " + fmt((*in)[k - 1]));
      }
    }
    if (s.interpolation == "CUBICSPLINE" && in->size() < 2) {
      ctx.error(sp + ".input", "CUBICSPLINE needs at least 2 keys, got " + std::to_string(in->size()));
    }
  }
  for (std::size_t ci = 0; ci < anim.channels.size(); ++ci) {
    const auto& ch = anim.channels[ci];
    const std::string cp = p + idx(".channels", ci);
    if (ch.sampler < 0 || static_cast<std::size_t>(ch.sampler) >= anim.samplers.size()) {
      ctx.error(cp + ".sampler", "index out of range");
      continue;
    }
    if (ch.target_node < 0 || static_cast<std::size_t>(ch.target_node) >= ctx.m.nodes.size()) {
      ctx.error(cp + ".target.node", "missing or out of range");
      continue;
    }
    const auto& s = anim.samplers[static_cast<std::size_t>(ch.sampler)];
    const std::string sp = p + idx(".samplers", static_cast<std::size_t>(ch.sampler));
    const bool cubic = s.interpolation == "CUBICSPLINE";
    if (s.input < 0 || s.output < 0 || static_cast<std::size_t>(s.input) >= ctx.m.accessors.size() ||
        static_cast<std::size_t>(s.output) >= ctx.m.accessors.size() || !ctx.accessor_ok[static_cast<std::size_t>(s.input)] ||
        !ctx.accessor_ok[static_cast<std::size_t>(s.output)]) {
      continue;
    }
    const auto keys = ctx.m.accessors[static_cast<std::size_t>(s.input)].count;
    const auto& oa = ctx.m.accessors[static_cast<std::size_t>(s.output)];
    const auto& out = ctx.accessor_values[static_cast<std::size_t>(s.output)];
    int comps = 0;
    if (ch.target_path == "translation" || ch.target_path == "scale") {
      comps = 3;
      if (oa.type != TINYGLTF_TYPE_VEC3) ctx.error(sp + ".output", "must be VEC3 for " + ch.target_path);
    } else if (ch.target_path == "rotation") {
      comps = 4;
      if (oa.type != TINYGLTF_TYPE_VEC4) ctx.error(sp + ".output", "must be VEC4 for rotation");
    } else if (ch.target_path == "weights") {
      const auto& nd = ctx.m.nodes[static_cast<std::size_t>(ch.target_node)];
      if (nd.mesh < 0 || static_cast<std::size_t>(nd.mesh) >= ctx.m.meshes.size() || ctx.m.meshes[static_cast<std::size_t>(nd.mesh)].primitives.empty() ||
          ctx.m.meshes[static_cast<std::size_t>(nd.mesh)].primitives[0].targets.empty()) {
        ctx.error(cp + ".target", "weights animation on a node without morph targets");
        continue;
      }
      comps = static_cast<int>(ctx.m.meshes[static_cast<std::size_t>(nd.mesh)].primitives[0].targets.size());
      if (oa.type != TINYGLTF_TYPE_SCALAR) ctx.error(sp + ".output", "must be SCALAR for weights");
    } else {
      ctx.error(cp + ".target.path", "unsupported path \"" + ch.target_path + "\"");
      continue;
    }
    const std::size_t per_key = std::size_t(comps) * (cubic ? 3 : 1);
    if (oa.count * std::size_t(type_components(oa.type)) != keys * per_key) {
      ctx.error(sp + ".output", "has " + std::to_string(oa.count) + " elements; " + std::to_string(keys) + " keys need " +
                                std::to_string(keys * per_key / std::size_t(std::max(1, type_components(oa.type)))));
      continue;
    }
    if (comps == 4 && oa.type == TINYGLTF_TYPE_VEC4) {
      for (std::size_t k = 0; k < keys; ++k) {
        const std::size_t base = k * per_key + (cubic ? 4 : 0);  // values only; tangents need not be unit
        double len = std::sqrt(out[base] * out[base] + out[base + 1] * out[base + 1] + out[base + 2] * out[base + 2] + out[base + 3] * out[base + 3]);
        if (std::abs(len - 1.0) > 1e-3) {
          ctx.error(cp + ".sampler", "rotation key " + std::to_string(k) + " (output elements " + std::to_string(base / 4 * 4) + ".." +
                                     std::to_string(base + 3) + ") is not a unit quaternion (|q| = " + fmt(len) + ")");
        }
      }
    }
  }
}


void convert_animations(const ConvertContext& ctx, Scene& s) {
  for (std::size_t ai = 0; ai < ctx.m.animations.size(); ++ai) {
    const auto& a = ctx.m.animations[ai];
    Animation out;
    out.name = a.name.empty() ? "animation" + std::to_string(ai) : a.name;
    out.start = std::numeric_limits<float>::max();
    out.end = 0.0f;
    std::map<std::pair<int, int>, int> sampler_for;  // (gltf sampler, components) -> ours
    for (const auto& ch : a.channels) {
      const auto& gs = a.samplers[static_cast<std::size_t>(ch.sampler)];
      TargetPath path = ch.target_path == "translation" ? TargetPath::Translation
                        : ch.target_path == "rotation"  ? TargetPath::Rotation
                        : ch.target_path == "scale"     ? TargetPath::Scale
                                                        : TargetPath::Weights;
      int comps = path == TargetPath::Rotation ? 4 : path == TargetPath::Weights
                                                         ? static_cast<int>(ctx.m.meshes[static_cast<std::size_t>(ctx.m.nodes[static_cast<std::size_t>(ch.target_node)].mesh)].primitives[0].targets.size())
                                                         : 3;
      auto key = std::make_pair(ch.sampler, comps);
      if (!sampler_for.count(key)) {
        AnimSampler sm;
        sm.interpolation = gs.interpolation == "STEP" ? Interpolation::Step : gs.interpolation == "CUBICSPLINE" ? Interpolation::CubicSpline : Interpolation::Linear;
        sm.components = comps;
        for (double v : ctx.accessor_values[static_cast<std::size_t>(gs.input)]) sm.input.push_back(static_cast<float>(v));
        for (double v : ctx.accessor_values[static_cast<std::size_t>(gs.output)]) sm.output.push_back(static_cast<float>(v));
        out.start = std::min(out.start, sm.input.front());
        out.end = std::max(out.end, sm.input.back());
        sampler_for[key] = static_cast<int>(out.samplers.size());
        out.samplers.push_back(std::move(sm));
      }
      out.channels.push_back({sampler_for[key], ch.target_node, path});
    }
    if (out.samplers.empty()) out.start = 0.0f;
    s.animations.push_back(std::move(out));
  }
}

}  // namespace meter::convert
