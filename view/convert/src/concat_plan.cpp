#include "meter/engine/concatenation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "meter/engine/animation.hpp"

namespace meter::engine {

using bridge::AlphaMode;
using bridge::AttributeSemantic;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Same camera choice and projection as Renderer::view_projection (a scene without a camera gets
// no screen test: the 3D x/y extents are compared instead, which is stricter for a front view).
bool camera_vp(const Scene& s, const std::vector<glm::mat4>& world, glm::mat4& vp) {
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    const Node& n = s.nodes[i];
    if (n.camera < 0) continue;
    const Camera& c = s.cameras[static_cast<std::size_t>(n.camera)];
    if (!s.config.camera.empty() && n.name != s.config.camera && c.name != s.config.camera) continue;
    glm::mat4 w = world[i];
    for (int k = 0; k < 3; ++k) w[k] = glm::vec4(glm::normalize(glm::vec3(w[k])), 0.0f);
    const float aspect = float(s.config.size[0]) / float(s.config.size[1]);
    glm::mat4 proj = c.perspective ? (c.zfar > 0 ? glm::perspective(c.yfov, aspect, c.znear, c.zfar) : glm::infinitePerspective(c.yfov, aspect, c.znear))
                                   : glm::ortho(-c.xmag, c.xmag, -c.ymag, c.ymag, c.znear, c.zfar);
    vp = proj * glm::inverse(w);
    return true;
  }
  return false;
}

// The sample times of animation a: every key and 8 steps inside each key interval.
std::vector<double> sample_times(const Animation& a) {
  std::set<double> t;
  for (const auto& sm : a.samplers) {
    for (std::size_t k = 0; k < sm.input.size(); ++k) {
      t.insert(sm.input[k]);
      if (k + 1 < sm.input.size()) {
        for (int j = 1; j < 8; ++j) t.insert(sm.input[k] + (sm.input[k + 1] - sm.input[k]) * j / 8.0);
      }
    }
  }
  return {t.begin(), t.end()};
}

std::string layout_key(const Primitive& p) {
  std::string k = std::to_string(p.stride);
  for (const auto& a : p.layout) k += "|" + std::to_string(int(a.semantic)) + "." + std::to_string(a.index) + "." + std::to_string(a.components) + "." + std::to_string(a.offset);
  return k;
}

// Order of two draws in the renderer's sorted list: opaque front-to-back, blended back-to-front,
// ties in draw order (stable sort). -1: a first, +1: b first, 0: depends on the animation state.
int order(const DrawExtent& a, int ai, const DrawExtent& b, int bi) {
  const bool fixed = a.key_min == a.key_max && b.key_min == b.key_max;
  int front_first;  // -1 when a is nearer
  if (a.key_max < b.key_min) front_first = -1;
  else if (b.key_max < a.key_min) front_first = 1;
  else if (fixed && a.key_min == b.key_min) return ai < bi ? -1 : 1;
  else return 0;
  return a.blend ? -front_first : front_first;
}

// Could drawing a and b in the other order change a pixel?
bool overlap(const DrawExtent& a, const DrawExtent& b) {
  if (a.screen_max.x <= b.screen_min.x || b.screen_max.x <= a.screen_min.x || a.screen_max.y <= b.screen_min.y ||
      b.screen_max.y <= a.screen_min.y) {
    return false;
  }
  if (a.blend || b.blend) return true;
  // Both depth-tested and depth-writing: only a depth tie (LEQUAL) makes the order visible.
  const float eps = 1e-5f * std::max(1.0f, std::max(std::abs(a.depth_max), std::abs(b.depth_max)));
  return !(a.depth_max + eps < b.depth_min || b.depth_max + eps < a.depth_min);
}

struct Planner {
  const Scene& s;
  std::vector<DrawExtent> ext;
  std::vector<int> unit;  // per draw: index of its unit (group id, or draw index + offset)
  std::map<int, std::vector<int>> node_draws;

  std::string node_name(int d) const { return "\"" + s.nodes[static_cast<std::size_t>(ext[static_cast<std::size_t>(d)].node)].name + "\""; }

  // All violations of the order/overlap rules among draws whose unit is in `units`, given `unit`.
  std::vector<std::string> conflicts(const std::set<int>& units) const {
    std::vector<std::string> out;
    std::map<int, int> rep;
    for (std::size_t d = 0; d < ext.size(); ++d) {
      if (!rep.count(unit[d])) rep[unit[d]] = static_cast<int>(d);
    }
    for (std::size_t a = 0; a < ext.size(); ++a) {
      for (std::size_t b = a + 1; b < ext.size(); ++b) {
        const int ua = unit[a], ub = unit[b];
        if (!units.count(ua) && !units.count(ub)) continue;
        if (ext[a].blend != ext[b].blend) continue;  // opaque pass always before the blended pass
        if (!overlap(ext[a], ext[b])) continue;
        const int ia = static_cast<int>(a), ib = static_cast<int>(b);
        if (ua == ub) {
          out.push_back(node_name(ia) + " and " + node_name(ib) + " overlap on screen" +
                        (ext[a].blend ? "" : " at intersecting depths") + ", so drawing them in one call could change the image");
          continue;
        }
        const int ra = rep.at(ua), rb = rep.at(ub);
        const int want = order(ext[a], ia, ext[b], ib);
        const int got = (ra == ia && rb == ib) ? want : order(ext[static_cast<std::size_t>(ra)], ra, ext[static_cast<std::size_t>(rb)], rb);
        if (want == 0 || got == 0 || want != got) {
          out.push_back(node_name(ia) + " overlaps " + node_name(ib) + " and their draw order " +
                        (want == 0 || got == 0 ? "changes with the animation state" : "would change") + " (merged draws sit at their representative " +
                        node_name(ra) + " / " + node_name(rb) + ")");
        }
      }
    }
    return out;
  }
};

}  // namespace

std::vector<DrawExtent> draw_extents(const Scene& s) {
  // Draw order = preorder from the roots, primitives in order (Converter::generate_programs).
  std::vector<DrawExtent> out;
  {
    std::vector<int> stack(s.roots.rbegin(), s.roots.rend());
    while (!stack.empty()) {
      const int n = stack.back();
      stack.pop_back();
      const Node& node = s.nodes[static_cast<std::size_t>(n)];
      stack.insert(stack.end(), node.children.rbegin(), node.children.rend());
      if (node.mesh < 0) continue;
      const Mesh& mesh = s.meshes[static_cast<std::size_t>(node.mesh)];
      for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
        DrawExtent e;
        e.node = n, e.primitive = static_cast<int>(p);
        e.blend = s.materials[static_cast<std::size_t>(mesh.primitives[p].material)].alpha == AlphaMode::Blend;
        e.screen_min = glm::vec2(kInf), e.screen_max = glm::vec2(-kInf);
        e.depth_min = e.key_min = kInf, e.depth_max = e.key_max = -kInf;
        out.push_back(e);
      }
    }
  }
  // Poses to evaluate: rest + every animation at its start, then each animation swept with the
  // others at their start and at their end.
  std::vector<std::pair<int, double>> sweeps;  // (animation, time) with -1 = none
  const std::size_t na = s.animations.size();
  std::vector<double> start(na), end(na);
  for (std::size_t a = 0; a < na; ++a) start[a] = s.animations[a].start, end[a] = s.animations[a].end;
  std::vector<glm::mat4> world;
  auto accumulate = [&](const Pose& pose) {
    world_matrices(s, pose, world);
    glm::mat4 vp(1.0f);
    const bool cam = camera_vp(s, world, vp);
    const float w = float(s.config.size[0]), h = float(s.config.size[1]);
    for (auto& e : out) {
      const Primitive& prim = s.meshes[static_cast<std::size_t>(s.nodes[static_cast<std::size_t>(e.node)].mesh)].primitives[static_cast<std::size_t>(e.primitive)];
      const glm::mat4 m = world[static_cast<std::size_t>(e.node)];
      for (int k = 0; k < 8; ++k) {
        glm::vec3 p((k & 1) ? prim.bounds_max.x : prim.bounds_min.x, (k & 2) ? prim.bounds_max.y : prim.bounds_min.y,
                    (k & 4) ? prim.bounds_max.z : prim.bounds_min.z);
        glm::vec4 wp = m * glm::vec4(p, 1.0f);
        glm::vec2 sp;
        float depth;
        if (cam) {
          glm::vec4 c = vp * wp;
          // Behind the eye: the projection is meaningless, take the whole screen.
          if (c.w <= 1e-6f) {
            sp = glm::vec2(-kInf);
            e.screen_min = glm::vec2(-kInf), e.screen_max = glm::vec2(kInf);
          } else {
            sp = glm::vec2((c.x / c.w * 0.5f + 0.5f) * w, (c.y / c.w * 0.5f + 0.5f) * h);
          }
          depth = c.w;
        } else {
          sp = glm::vec2(wp.x, wp.y);
          depth = -wp.z;
        }
        if (std::isfinite(sp.x)) e.screen_min = glm::min(e.screen_min, sp), e.screen_max = glm::max(e.screen_max, sp);
        e.depth_min = std::min(e.depth_min, depth), e.depth_max = std::max(e.depth_max, depth);
      }
      const glm::vec3 c = (prim.bounds_min + prim.bounds_max) * 0.5f;
      const float key = cam ? (vp * m * glm::vec4(c, 1.0f)).w : 0.0f;
      e.key_min = std::min(e.key_min, key), e.key_max = std::max(e.key_max, key);
    }
  };
  for (int others = 0; others < 2; ++others) {
    Pose base = Pose::rest(s);
    for (std::size_t a = 0; a < na; ++a) apply_animation(s, static_cast<int>(a), others ? end[a] : start[a], base);
    if (na == 0 || others == 0) accumulate(base);
    for (std::size_t a = 0; a < na; ++a) {
      for (double t : sample_times(s.animations[a])) {
        Pose p = base;
        apply_animation(s, static_cast<int>(a), t, p);
        accumulate(p);
      }
    }
  }
  // Half a pixel of margin: anti-aliased edges and MSAA samples reach that far past the geometry.
  for (auto& e : out) e.screen_min -= glm::vec2(0.5f), e.screen_max += glm::vec2(0.5f);
  return out;
}

ConcatPlan plan_groups(const Scene& s, const std::vector<Group>& configured, bool propose, const std::string& origin) {
  ConcatPlan plan;
  Planner pl{s, draw_extents(s), {}, {}};
  const int n_draws = static_cast<int>(pl.ext.size());
  const int kSingle = 1 << 20;  // unit ids of ungrouped draws: kSingle + draw index
  pl.unit.resize(pl.ext.size());
  for (int d = 0; d < n_draws; ++d) pl.unit[static_cast<std::size_t>(d)] = kSingle + d, pl.node_draws[pl.ext[static_cast<std::size_t>(d)].node].push_back(d);

  std::set<int> used_nodes;
  std::map<int, std::string> unit_name;  // accepted group unit id -> group name
  // Static reasons a node cannot be a member; "" when it can. Sets material / layout of the node.
  auto member_problem = [&](int node, int& material, std::string& layout) -> std::string {
    const Node& n = s.nodes[static_cast<std::size_t>(node)];
    if (n.mesh < 0) return "has no mesh";
    if (n.skin >= 0) return "is skinned (joint matrices are per draw)";
    const Mesh& m = s.meshes[static_cast<std::size_t>(n.mesh)];
    material = -1;
    for (const auto& p : m.primitives) {
      if (p.morph_targets > 0) return "has morph targets (not merged: the CPU path handles rigid transforms only)";
      if (material >= 0 && p.material != material) return "has primitives with different materials";
      material = p.material;
      layout = layout_key(p);
    }
    if (material < 0) return "has no primitives";
    return "";
  };

  auto group_id = [&](std::size_t g) { return static_cast<int>(g); };
  for (std::size_t g = 0; g < configured.size(); ++g) {
    const Group& grp = configured[g];
    GroupDecision dec;
    dec.group = grp.name;
    dec.members = grp.members;
    std::vector<std::string> errs;
    int material = -1;
    std::string layout, first;
    std::vector<int> nodes;
    for (const auto& name : grp.members) {
      const int node = s.find_node(name);
      if (node < 0) { errs.push_back("no node named \"" + name + "\""); continue; }
      if (used_nodes.count(node)) { errs.push_back("\"" + name + "\" is already a member of another group"); continue; }
      int mat = -1;
      std::string lay;
      std::string why = member_problem(node, mat, lay);
      if (!why.empty()) { errs.push_back("\"" + name + "\" " + why); continue; }
      if (material < 0) material = mat, layout = lay, first = name;
      else if (mat != material) {
        errs.push_back("\"" + name + "\" uses material \"" + s.materials[static_cast<std::size_t>(mat)].name + "\" but \"" + first + "\" uses \"" +
                       s.materials[static_cast<std::size_t>(material)].name + "\" (one draw has one material)");
        continue;
      } else if (lay != layout) {
        errs.push_back("\"" + name + "\" has a different vertex layout from \"" + first + "\"");
        continue;
      }
      used_nodes.insert(node);
      nodes.push_back(node);
    }
    if (grp.members.size() < 2) errs.push_back("a group needs at least two members");
    if (errs.empty()) {
      for (int node : nodes) for (int d : pl.node_draws[node]) pl.unit[static_cast<std::size_t>(d)] = group_id(g);
      for (auto& c : pl.conflicts({group_id(g)})) errs.push_back(c);
    }
    if (!errs.empty()) {
      std::string msg = origin + ": scene config $.groups[" + std::to_string(g) + "] (\"" + grp.name + "\") cannot be merged:";
      for (const auto& e : errs) msg += "\n  - " + e;
      throw SceneError(msg);
    }
    dec.accepted = true;
    unit_name[group_id(g)] = grp.name;
    dec.reasons.push_back("one material \"" + s.materials[static_cast<std::size_t>(material)].name + "\", same vertex layout, no skin/morph");
    dec.reasons.push_back("no overlap among members and no draw-order change against other draws over all animation ranges");
    plan.decisions.push_back(std::move(dec));
  }

  if (propose) {
    // Candidates in draw order, bucketed by material + layout (blend state follows the material).
    std::map<std::pair<int, std::string>, std::vector<int>> buckets;
    std::vector<std::pair<int, std::string>> bucket_order;
    for (int d = 0; d < n_draws; ++d) {
      const int node = pl.ext[static_cast<std::size_t>(d)].node;
      if (pl.ext[static_cast<std::size_t>(d)].primitive != 0 || used_nodes.count(node)) continue;
      int mat = -1;
      std::string lay;
      std::string why = member_problem(node, mat, lay);
      if (!why.empty()) {
        GroupDecision dec;
        dec.group = "(not proposed)";
        dec.members = {s.nodes[static_cast<std::size_t>(node)].name};
        dec.reasons.push_back("\"" + s.nodes[static_cast<std::size_t>(node)].name + "\" " + why);
        plan.decisions.push_back(std::move(dec));
        continue;
      }
      auto key = std::make_pair(mat, lay);
      if (!buckets.count(key)) bucket_order.push_back(key);
      buckets[key].push_back(node);
    }
    int next_id = static_cast<int>(configured.size());
    for (const auto& key : bucket_order) {
      const auto& cand = buckets[key];
      const std::string mat_name = s.materials[static_cast<std::size_t>(key.first)].name;
      std::vector<bool> taken(cand.size(), false);
      for (std::size_t i = 0; i < cand.size(); ++i) {
        if (taken[i]) continue;
        const int id = next_id;
        std::vector<int> members{cand[i]};
        std::vector<std::string> refused;
        for (int d : pl.node_draws[cand[i]]) pl.unit[static_cast<std::size_t>(d)] = id;
        for (std::size_t j = i + 1; j < cand.size(); ++j) {
          if (taken[j]) continue;
          for (int d : pl.node_draws[cand[j]]) pl.unit[static_cast<std::size_t>(d)] = id;
          auto c = pl.conflicts({id});
          if (c.empty()) {
            members.push_back(cand[j]);
            taken[j] = true;
          } else {
            for (int d : pl.node_draws[cand[j]]) pl.unit[static_cast<std::size_t>(d)] = kSingle + d;
            refused.push_back("\"" + s.nodes[static_cast<std::size_t>(cand[j])].name + "\" left out: " + c.front());
          }
        }
        taken[i] = true;
        GroupDecision dec;
        for (int m : members) dec.members.push_back(s.nodes[static_cast<std::size_t>(m)].name);
        if (members.size() < 2) {
          for (int d : pl.node_draws[cand[i]]) pl.unit[static_cast<std::size_t>(d)] = kSingle + d;
          dec.group = "(not proposed)";
          dec.reasons.push_back("no other object with material \"" + mat_name + "\" can join it without overlap or an order change");
        } else {
          dec.group = "auto_" + std::to_string(next_id - static_cast<int>(configured.size())) + "_" + mat_name;
          dec.accepted = true;
          unit_name[id] = dec.group;
          dec.reasons.push_back("same material \"" + mat_name + "\" (blend " + (pl.ext[static_cast<std::size_t>(pl.node_draws[cand[i]][0])].blend ? "on" : "off") +
                                "), same vertex layout, no overlap / order change over the animation ranges");
          ++next_id;
        }
        // Only the first few refusals: a 40-member bucket would otherwise print 40 x 40 lines.
        for (std::size_t r = 0; r < refused.size() && r < 3; ++r) dec.reasons.push_back(refused[r]);
        if (refused.size() > 3) dec.reasons.push_back("... " + std::to_string(refused.size() - 3) + " more left out");
        plan.decisions.push_back(std::move(dec));
      }
    }
  }
  // Accepted groups in the plan with members in draw order.
  std::map<int, std::vector<int>> by_unit;
  for (int d = 0; d < n_draws; ++d) {
    const int u = pl.unit[static_cast<std::size_t>(d)];
    if (u < kSingle && pl.ext[static_cast<std::size_t>(d)].primitive == 0) by_unit[u].push_back(pl.ext[static_cast<std::size_t>(d)].node);
  }
  for (const auto& [u, nodes] : by_unit) {
    Group g;
    g.name = unit_name.at(u);
    for (int node : nodes) g.members.push_back(s.nodes[static_cast<std::size_t>(node)].name);
    plan.groups.push_back(std::move(g));
  }
  return plan;
}

std::string concat_report(const ConcatPlan& plan) {
  std::ostringstream os;
  std::size_t merged = 0;
  for (const auto& g : plan.groups) merged += g.members.size();
  os << "concatenation: " << plan.groups.size() << " group(s) merging " << merged << " object(s) into " << plan.groups.size() << " draw(s)\n";
  for (const auto& d : plan.decisions) {
    os << (d.accepted ? "group " : "") << d.group << (d.accepted ? " (merged, " + std::to_string(d.members.size()) + " objects)" : "") << ":";
    if (d.members.size() <= 6) {
      for (const auto& m : d.members) os << " " << m;
    } else {
      os << " " << d.members.front() << " ... " << d.members.back();
    }
    os << "\n";
    for (const auto& r : d.reasons) os << "  " << r << "\n";
  }
  return os.str();
}

void attach_groups(Scene& s, const ConcatPlan& plan) {
  s.groups.clear();
  for (const auto& g : plan.groups) {
    MergedGroup mg;
    mg.name = g.name;
    std::set<int> nodes;
    for (const auto& m : g.members) nodes.insert(s.find_node(m));
    for (std::size_t d = 0; d < s.draws.size(); ++d) {
      if (nodes.count(s.draws[d].node)) mg.draws.push_back(static_cast<int>(d));
    }
    s.groups.push_back(std::move(mg));
  }
  const std::string why = check_groups(s);
  if (!why.empty()) throw SceneError(s.source_name + ": " + why);
}

std::string check_groups(const Scene& s) {
  std::set<int> seen;
  for (std::size_t g = 0; g < s.groups.size(); ++g) {
    const auto& mg = s.groups[g];
    const std::string p = "groups[" + std::to_string(g) + "] (\"" + mg.name + "\"): ";
    if (mg.draws.empty()) return p + "no draws";
    int program = -1;
    std::string layout;
    for (int d : mg.draws) {
      if (d < 0 || static_cast<std::size_t>(d) >= s.draws.size()) return p + "draw index " + std::to_string(d) + " out of range";
      if (!seen.insert(d).second) return p + "draw " + std::to_string(d) + " is in two groups";
      const DrawItem& di = s.draws[static_cast<std::size_t>(d)];
      const Primitive& prim = s.meshes[static_cast<std::size_t>(di.mesh)].primitives[static_cast<std::size_t>(di.primitive)];
      if (program < 0) program = di.program, layout = layout_key(prim);
      if (di.program != program) return p + "members use different programs";
      if (layout_key(prim) != layout) return p + "members have different vertex layouts";
      if (prim.morph_targets > 0 || s.nodes[static_cast<std::size_t>(di.node)].skin >= 0) return p + "a member is skinned or morphed";
    }
    const auto& prog = s.programs[static_cast<std::size_t>(program)].program;
    // (not Program::find_attribute: the runtime library uses shadergen's headers only)
    if (std::none_of(prog.attributes.begin(), prog.attributes.end(), [](const auto& a) { return a.semantic == AttributeSemantic::VertexAlpha; })) {
      return p + "the program has no vertex alpha attribute";
    }
    if (prog.features.skin_joints > 0 || prog.features.morph_targets > 0) return p + "the program skins or morphs";
  }
  return "";
}

void transform_member(const Primitive& src, const glm::mat4& world, float alpha, std::span<float> dst) {
  const int out_stride = merged_stride(src);
  const glm::mat3 normal = glm::inverseTranspose(glm::mat3(world));
  const glm::mat3 linear(world);
  for (std::uint32_t v = 0; v < src.vertex_count; ++v) {
    const float* in = src.vertices.data() + std::size_t(v) * std::size_t(src.stride);
    float* out = dst.data() + std::size_t(v) * std::size_t(out_stride);
    std::copy(in, in + src.stride, out);
    for (const auto& a : src.layout) {
      float* o = out + a.offset;
      const float* i = in + a.offset;
      if (a.semantic == AttributeSemantic::Position) {
        const glm::vec4 p = world * glm::vec4(i[0], i[1], i[2], 1.0f);
        o[0] = p.x, o[1] = p.y, o[2] = p.z;
      } else if (a.semantic == AttributeSemantic::Normal) {
        const glm::vec3 n = normal * glm::vec3(i[0], i[1], i[2]);
        o[0] = n.x, o[1] = n.y, o[2] = n.z;
      } else if (a.semantic == AttributeSemantic::Tangent) {
        const glm::vec3 t = linear * glm::vec3(i[0], i[1], i[2]);
        o[0] = t.x, o[1] = t.y, o[2] = t.z;
      }
    }
    out[src.stride] = alpha;
  }
}

void set_member_alpha(const Primitive& src, float alpha, std::span<float> dst) {
  const int out_stride = merged_stride(src);
  for (std::uint32_t v = 0; v < src.vertex_count; ++v) dst[std::size_t(v) * std::size_t(out_stride) + std::size_t(src.stride)] = alpha;
}

void append_member_indices(const Primitive& src, std::uint32_t base, bool mirror, std::vector<std::uint32_t>& out) {
  for (std::size_t i = 0; i + 2 < src.indices.size(); i += 3) {
    if (mirror) {
      out.insert(out.end(), {base + src.indices[i], base + src.indices[i + 2], base + src.indices[i + 1]});
    } else {
      out.insert(out.end(), {base + src.indices[i], base + src.indices[i + 1], base + src.indices[i + 2]});
    }
  }
}

}  // namespace meter::engine
