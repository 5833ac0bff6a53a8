// Mesh validation: primitive modes, attribute types and counts, unit normals and tangents, colour
// ranges, joint indices against the skins that use the mesh, weight sums, indices and morph
// targets. Problems with one obviously right answer are reported as repairs.
#include <algorithm>
#include <cmath>

#include "convert_context.hpp"
#include "meter/shadergen/shadergen.hpp"

namespace meter::convert {

namespace {

int max_joint_count(const tinygltf::Model& m, std::size_t mesh) {
  int count = -1;
  for (const auto& nd : m.nodes) {
    if (nd.mesh == static_cast<int>(mesh) && nd.skin >= 0 && static_cast<std::size_t>(nd.skin) < m.skins.size()) {
      int jc = static_cast<int>(m.skins[static_cast<std::size_t>(nd.skin)].joints.size());
      count = count < 0 ? jc : std::min(count, jc);
    }
  }
  return count;
}

// Unit-length check (tolerance as the Khronos validator's order of magnitude, loose enough for
// quantised data): slightly off is renormalised, clearly wrong is an error.
void check_unit_vectors(ConvertContext& ctx, const std::vector<double>& d, std::size_t stride, std::size_t n, const std::string& path) {
  for (std::size_t e = 0; e + stride <= d.size(); e += stride) {
    double len = 0;
    for (std::size_t c = 0; c < n; ++c) len += d[e + c] * d[e + c];
    len = std::sqrt(len);
    if (std::abs(len - 1.0) > 0.01) {
      ctx.error(path, "vector at element " + std::to_string(e / stride) + " is not unit length (|v| = " + fmt(len) + ")");
    }
  }
}

void check_joints(ConvertContext& ctx, const tinygltf::Primitive& prim, std::size_t mi, const std::string& jname, const std::vector<double>& joints,
                  const std::string& ap) {
  const int jc = max_joint_count(ctx.m, mi);
  const auto wit = prim.attributes.find("WEIGHTS_" + jname.substr(7));
  const std::vector<double>* weights =
      (wit != prim.attributes.end() && wit->second >= 0 && static_cast<std::size_t>(wit->second) < ctx.accessor_ok.size() &&
       ctx.accessor_ok[static_cast<std::size_t>(wit->second)])
          ? &ctx.accessor_values[static_cast<std::size_t>(wit->second)]
          : nullptr;
  // Every joint set of this vertex, to find duplicates across JOINTS_0 / JOINTS_1.
  for (std::size_t e = 0; e < joints.size(); ++e) {
    const std::size_t v = e / 4;
    const double j = joints[e];
    const double w = weights && weights->size() == joints.size() ? (*weights)[e] : 1.0;
    if (jc >= 0 && j >= jc) {
      ctx.error(ap, "element " + std::to_string(v) + " (component " + std::to_string(e % 4) + ") has joint " + fmt(j) +
                    " but the skin has only " + std::to_string(jc) + " joints");
      continue;
    }
    if (w == 0.0) continue;
    // Duplicate: the same joint used earlier for this vertex with non-zero weight.
    for (const auto& [other, acc] : prim.attributes) {
      if (other.rfind("JOINTS_", 0) != 0 || other > jname || acc < 0 || static_cast<std::size_t>(acc) >= ctx.accessor_ok.size() ||
          !ctx.accessor_ok[static_cast<std::size_t>(acc)]) {
        continue;
      }
      const auto& oj = ctx.accessor_values[static_cast<std::size_t>(acc)];
      const std::size_t limit = other == jname ? e % 4 : 4;
      for (std::size_t c = 0; c < limit && v * 4 + c < oj.size(); ++c) {
        if (oj[v * 4 + c] == j) {
          ctx.error(ap, "element " + std::to_string(v) + " (component " + std::to_string(e % 4) + ") repeats joint " + fmt(j) + " already used by this vertex");
        }
      }
    }
  }
}

void check_weight_sums(ConvertContext& ctx, const tinygltf::Primitive& prim, const std::string& pp) {
  std::vector<const std::vector<double>*> sets;
  std::vector<std::string> names;
  for (const auto& [name, acc] : prim.attributes) {
    if (name.rfind("WEIGHTS_", 0) == 0 && acc >= 0 && static_cast<std::size_t>(acc) < ctx.accessor_ok.size() &&
        ctx.accessor_ok[static_cast<std::size_t>(acc)]) {
      sets.push_back(&ctx.accessor_values[static_cast<std::size_t>(acc)]);
      names.push_back(name);
    }
  }
  if (sets.empty()) return;
  const std::size_t verts = sets[0]->size() / 4;
  for (std::size_t v = 0; v < verts; ++v) {
    double sum = 0;
    for (const auto* s : sets) {
      for (std::size_t c = 0; c < 4 && v * 4 + c < s->size(); ++c) sum += (*s)[v * 4 + c];
    }
    bool negative = false;
    for (const auto* st : sets) {
      for (std::size_t c = 0; c < 4 && v * 4 + c < st->size(); ++c) negative = negative || (*st)[v * 4 + c] < 0;
    }
    if (negative) {  // the sum of a set with a negative weight is meaningless: no repair possible
      for (const auto& n : names) ctx.error(pp + ".attributes." + n, "weights of element " + std::to_string(v) + " are not normalised (a weight is negative)");
      continue;
    }
    const bool total_off = std::abs(sum - 1.0) > 2e-3 * double(sets.size() * 4);
    for (std::size_t k = 0; k < sets.size(); ++k) {
      double own = 0;
      for (std::size_t c = 0; c < 4 && v * 4 + c < sets[k]->size(); ++c) own += (*sets[k])[v * 4 + c];
      // One set alone above 1 is wrong whatever the other sets hold.
      if (total_off || own > 1.0 + 8e-3) {
        ctx.repair(pp + ".attributes." + names[k], "weights of element " + std::to_string(v) + " sum to " + fmt(total_off ? sum : own) +
                                                ": renormalised to 1");
      }
    }
  }
}

// The primitive's mode and its POSITION accessor; returns the vertex count (0: unknown).
std::size_t check_mode_and_position(ConvertContext& ctx, const tinygltf::Primitive& prim, const std::string& pp) {
  if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
      prim.mode != TINYGLTF_MODE_TRIANGLE_FAN && prim.mode != -1) {
    ctx.error(pp + ".mode", "primitive mode " + std::to_string(prim.mode) + " (points/lines) is not supported; only triangles");
  }
  auto pos_it = prim.attributes.find("POSITION");
  if (pos_it == prim.attributes.end()) {
    ctx.error(pp + ".attributes", "POSITION is required");
    return 0;
  }
  if (ctx.use_accessor(pos_it->second, pp + ".attributes.POSITION", {TINYGLTF_TYPE_VEC3}, {}))
    return ctx.m.accessors[static_cast<std::size_t>(pos_it->second)].count;
  return 0;
}

// One vertex attribute: its count against POSITION, its type, and the values its semantic
// constrains (unit normals and tangents, colours in 0..1, joints and weights).
void check_attribute(ConvertContext& ctx, const tinygltf::Primitive& prim, std::size_t mi, const std::string& name, int acc,
                     std::size_t vcount, const std::string& ap) {
  if (acc >= 0 && static_cast<std::size_t>(acc) < ctx.m.accessors.size() && vcount &&
      ctx.m.accessors[static_cast<std::size_t>(acc)].count != vcount) {
    ctx.error(ap, "has " + std::to_string(ctx.m.accessors[static_cast<std::size_t>(acc)].count) + " elements but POSITION has " + std::to_string(vcount));
    return;
  }
  if (name == "NORMAL") {
    if (auto* d = ctx.use_accessor(acc, ap, {TINYGLTF_TYPE_VEC3}, {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT})) {
      check_unit_vectors(ctx, *d, 3, 3, ap);
    }
  } else if (name == "TANGENT") {
    if (auto* d = ctx.use_accessor(acc, ap, {TINYGLTF_TYPE_VEC4}, {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT})) {
      check_unit_vectors(ctx, *d, 4, 3, ap);
      for (std::size_t e = 0; e < d->size() / 4; ++e) {
        double w = (*d)[e * 4 + 3];
        if (w != 1.0 && w != -1.0) {
          ctx.repair(ap, "element " + std::to_string(e) + " has w = " + fmt(w) + " (must be +-1): set to " + (w < 0 ? "-1" : "+1"));
        }
      }
    }
  } else if (name.rfind("TEXCOORD_", 0) == 0) {
    ctx.use_accessor(acc, ap, {TINYGLTF_TYPE_VEC2}, {});
  } else if (name.rfind("COLOR_", 0) == 0) {
    if (auto* d = ctx.use_accessor(acc, ap, {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4},
                               {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT})) {
      for (std::size_t e = 0; e < d->size(); ++e) {
        if ((*d)[e] < 0.0 || (*d)[e] > 1.0) {
          ctx.repair(ap, "component " + std::to_string(e) + " = " + fmt((*d)[e]) + " outside 0..1: clamped");
        }
      }
    }
  } else if (name.rfind("JOINTS_", 0) == 0) {
    auto* d = ctx.use_accessor(acc, ap, {TINYGLTF_TYPE_VEC4}, {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT});
    std::string wname = "WEIGHTS_" + name.substr(7);
    auto wit = prim.attributes.find(wname);
    if (wit == prim.attributes.end()) {
      ctx.error(ap, "has no matching " + wname);
    } else if (d) {
      check_joints(ctx, prim, mi, name, *d, ap);
    }
    if (name != "JOINTS_0") ctx.error(ap, "more than 4 joint influences per vertex are not supported");
  } else if (name.rfind("WEIGHTS_", 0) == 0) {
    if (auto* d = ctx.use_accessor(acc, ap, {TINYGLTF_TYPE_VEC4}, {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT})) {
      for (std::size_t e = 0; e < d->size(); ++e) {
        if ((*d)[e] < 0) ctx.error(ap, "element " + std::to_string(e / 4) + " (component " + std::to_string(e % 4) + ") has negative weight " + fmt((*d)[e]));
      }
    }
  } else if (name == "POSITION") {
  } else if (!name.empty() && name[0] == '_') {
    // application-specific attribute: ignored
  } else {
    ctx.error(ap, "unknown attribute semantic");
  }
}

// The index accessor: type, restart values, range, triangle count and degenerate triangles; or,
// without indices, a vertex count that makes whole triangles.
void check_indices(ConvertContext& ctx, const tinygltf::Primitive& prim, std::size_t vcount, const std::string& pp) {
  if (prim.indices >= 0) {
    if (auto* d = ctx.use_accessor(prim.indices, pp + ".indices", {TINYGLTF_TYPE_SCALAR},
                               {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT})) {
      const int ct = ctx.m.accessors[static_cast<std::size_t>(prim.indices)].componentType;
      const double restart = ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ? 255.0 : ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 65535.0 : 4294967295.0;
      for (std::size_t e = 0; e < d->size(); ++e) {
        if ((*d)[e] == restart) {
          ctx.error(pp + ".indices", "element " + std::to_string(e) + " is the primitive restart value " + fmt(restart));
        } else if (vcount && (*d)[e] >= double(vcount)) {
          ctx.error(pp + ".indices", "element " + std::to_string(e) + " has value " + fmt((*d)[e]) + " but there are only " + std::to_string(vcount) + " vertices");
        }
      }
      if (prim.mode == TINYGLTF_MODE_TRIANGLES || prim.mode == -1) {
        if (d->size() % 3) ctx.error(pp + ".indices", "count " + std::to_string(d->size()) + " is not a multiple of 3");
        std::size_t degenerate = 0;
        for (std::size_t e = 0; e + 2 < d->size(); e += 3) {
          if ((*d)[e] == (*d)[e + 1] || (*d)[e] == (*d)[e + 2] || (*d)[e + 1] == (*d)[e + 2]) ++degenerate;
        }
        if (degenerate) ctx.repair(pp + ".indices", std::to_string(degenerate) + " degenerate triangle(s) of " + std::to_string(d->size() / 3) + " dropped");
      }
    }
  } else if ((prim.mode == TINYGLTF_MODE_TRIANGLES || prim.mode == -1) && vcount % 3) {
    ctx.error(pp + ".attributes.POSITION", "non-indexed triangles need a vertex count that is a multiple of 3");
  }
}

// Each morph target's attributes: supported semantics and POSITION's element count.
void check_morph_targets(ConvertContext& ctx, const tinygltf::Primitive& prim, std::size_t vcount, const std::string& pp) {
  for (std::size_t ti = 0; ti < prim.targets.size(); ++ti) {
    for (const auto& [name, acc] : prim.targets[ti]) {
      const std::string tp = pp + idx(".targets", ti) + "." + name;
      if (name != "POSITION" && name != "NORMAL" && name != "TANGENT") {
        ctx.error(tp, "unsupported morph target attribute");
      } else if (ctx.use_accessor(acc, tp, {TINYGLTF_TYPE_VEC3}, {}) && vcount &&
                 ctx.m.accessors[static_cast<std::size_t>(acc)].count != vcount) {
        ctx.error(tp, "element count differs from POSITION");
      }
    }
  }
}

}  // namespace

void validate_mesh(ConvertContext& ctx, std::size_t mi) {
  const auto& mesh = ctx.m.meshes[mi];
  const std::string mp = idx("meshes", mi);
  if (mesh.primitives.empty()) ctx.error(mp + ".primitives", "a mesh needs at least one primitive");
  std::size_t targets0 = 0;
  for (std::size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
    const auto& prim = mesh.primitives[pi];
    const std::string pp = mp + idx(".primitives", pi);
    const std::size_t vcount = check_mode_and_position(ctx, prim, pp);
    for (const auto& [name, acc] : prim.attributes) check_attribute(ctx, prim, mi, name, acc, vcount, pp + ".attributes." + name);
    check_weight_sums(ctx, prim, pp);
    check_indices(ctx, prim, vcount, pp);
    if (prim.material >= 0 && static_cast<std::size_t>(prim.material) >= ctx.m.materials.size()) {
      ctx.error(pp + ".material", "index out of range");
    }
    if (pi == 0) targets0 = prim.targets.size();
    else if (prim.targets.size() != targets0) ctx.error(pp + ".targets", "all primitives of a mesh need the same number of morph targets");
    if (prim.targets.size() > std::size_t(shadergen::kMaxMorphTargets)) {
      ctx.error(pp + ".targets", std::to_string(prim.targets.size()) + " morph targets; at most " + std::to_string(shadergen::kMaxMorphTargets) + " are supported");
    }
    check_morph_targets(ctx, prim, vcount, pp);
  }
  if (!mesh.weights.empty() && mesh.weights.size() != targets0) ctx.error(mp + ".weights", "count differs from the number of morph targets");
}

}  // namespace meter::convert
