#include "meter/convert/concat_plan.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "meter/engine/merged_draws.hpp"
#include "programs/program_features.hpp"

namespace meter::convert {

using engine::vertex_layout_key;
using engine::check_groups;

namespace {

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

// Static reasons a node cannot be a member; "" when it can. Sets the node's material and vertex
// layout.
std::string member_problem(const Scene& s, int node, int& material, std::string& layout) {
  const Node& n = s.nodes[static_cast<std::size_t>(node)];
  if (n.mesh < 0) return "has no mesh";
  if (n.skin >= 0) return "is skinned (joint matrices are per draw)";
  const Mesh& m = s.meshes[static_cast<std::size_t>(n.mesh)];
  material = -1;
  for (const auto& p : m.primitives) {
    if (p.morph_targets > 0) return "has morph targets (not merged: the CPU path handles rigid transforms only)";
    if (material >= 0 && p.material != material) return "has primitives with different materials";
    material = p.material;
    layout = vertex_layout_key(p);
  }
  if (material < 0) return "has no primitives";
  return "";
}

// The planning state: which unit (merged group, or the draw alone) each draw belongs to, the
// nodes already taken by a group, and the decisions made so far.
struct Planner {
  static constexpr int kSingle = 1 << 20;  // unit ids of ungrouped draws: kSingle + draw index

  const Scene& s;
  std::vector<DrawExtent> ext;
  std::vector<int> unit;  // per draw: index of its unit (group id, or draw index + offset)
  std::map<int, std::vector<int>> node_draws;
  std::set<int> used_nodes;
  std::map<int, std::string> unit_name;  // accepted group unit id -> group name
  ConcatPlan plan;
  const ConcatenationCosts* costs = nullptr;  // the break-even test's; null: every allowed group is merged
  std::vector<char> moving;                   // per node: its world matrix can change (dynamic_nodes)

  Planner(const Scene& scene, const ConcatenationCosts* merge_costs)
      : s(scene), ext(draw_extents(scene)), costs(merge_costs), moving(dynamic_nodes(scene)) {
    unit.resize(ext.size());
    for (std::size_t d = 0; d < ext.size(); ++d) {
      unit[d] = kSingle + static_cast<int>(d);
      node_draws[ext[d].node].push_back(static_cast<int>(d));
    }
  }

  int draw_count() const { return static_cast<int>(ext.size()); }
  std::string node_name(int d) const { return "\"" + s.nodes[static_cast<std::size_t>(ext[static_cast<std::size_t>(d)].node)].name + "\""; }
  const std::string& material_name(int material) const { return s.materials[static_cast<std::size_t>(material)].name; }

  // Eq. 1-3 for merging the draws of `nodes` (merge_break_even.hpp); nothing without costs.
  std::optional<MergePrediction> predict(const std::vector<int>& nodes) const {
    if (!costs) return std::nullopt;
    int objects = 0;
    std::uint64_t vertices = 0, moving_vertices = 0;
    for (int node : nodes) {
      const Node& n = s.nodes[static_cast<std::size_t>(node)];
      for (int d : node_draws.at(node)) {
        const auto prim = static_cast<std::size_t>(ext[static_cast<std::size_t>(d)].primitive);
        const std::uint32_t v = s.meshes[static_cast<std::size_t>(n.mesh)].primitives[prim].vertex_count;
        ++objects;
        vertices += v;
        if (moving[static_cast<std::size_t>(node)]) moving_vertices += v;
      }
    }
    return predict_merge(*costs, objects, vertices, moving_vertices);
  }

  // Whether `node` joining `members` makes the merge save more (its draw saved is worth more than
  // transforming its vertices when it moves); always without costs.
  bool joining_pays(std::vector<int> members, int node) const {
    if (!costs) return true;
    const MergePrediction without = *predict(members);
    members.push_back(node);
    const MergePrediction with = *predict(members);
    return with.before_ms - with.after_ms > without.before_ms - without.after_ms;
  }

  // Puts every draw of `node` in unit `id` (kSingle: back on their own).
  void assign(int node, int id) {
    for (int d : node_draws[node]) unit[static_cast<std::size_t>(d)] = id == kSingle ? kSingle + d : id;
  }

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

  // A group the scene config names: every member must be mergeable with the first, and merging
  // them must change no pixel. Anything else is an error naming the group and each reason.
  void accept_configured(int id, const Group& grp, const std::string& origin) {
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
      std::string why = member_problem(s, node, mat, lay);
      if (!why.empty()) { errs.push_back("\"" + name + "\" " + why); continue; }
      if (material < 0) material = mat, layout = lay, first = name;
      else if (mat != material) {
        errs.push_back("\"" + name + "\" uses material \"" + material_name(mat) + "\" but \"" + first + "\" uses \"" +
                       material_name(material) + "\" (one draw has one material)");
        continue;
      } else if (lay != layout) {
        errs.push_back("\"" + name + "\" has a different vertex layout from \"" + first + "\"");
        continue;
      }
      used_nodes.insert(node);
      nodes.push_back(node);
    }
    if (grp.members.size() < 2) errs.push_back("a group needs at least two members");
    // A group that would not pay stays unmerged (its members are not proposed elsewhere either).
    const std::optional<MergePrediction> cost = errs.empty() ? predict(nodes) : std::nullopt;
    if (cost && !cost->pays()) {
      plan.decisions.push_back({grp.name, false, grp.members, {describe(*cost)}});
      return;
    }
    if (errs.empty()) {
      for (int node : nodes) assign(node, id);
      for (auto& c : conflicts({id})) errs.push_back(c);
    }
    if (!errs.empty()) {
      std::string msg = origin + ": scene config $.groups[" + std::to_string(id) + "] (\"" + grp.name + "\") cannot be merged:";
      for (const auto& e : errs) msg += "\n  - " + e;
      throw SceneError(msg);
    }
    GroupDecision dec;
    dec.group = grp.name;
    dec.members = grp.members;
    dec.accepted = true;
    unit_name[id] = grp.name;
    dec.reasons.push_back("one material \"" + material_name(material) + "\", same vertex layout, no skin/morph");
    dec.reasons.push_back("no overlap among members and no draw-order change against other draws over all animation ranges");
    if (cost) dec.reasons.push_back(describe(*cost));
    plan.decisions.push_back(std::move(dec));
  }

  // Candidates for proposed groups in draw order, bucketed by material + layout (blend state
  // follows the material). A node that can never be a member gets its "not proposed" decision.
  std::vector<std::pair<std::pair<int, std::string>, std::vector<int>>> candidate_buckets() {
    std::map<std::pair<int, std::string>, std::vector<int>> buckets;
    std::vector<std::pair<int, std::string>> bucket_order;
    for (int d = 0; d < draw_count(); ++d) {
      const int node = ext[static_cast<std::size_t>(d)].node;
      if (ext[static_cast<std::size_t>(d)].primitive != 0 || used_nodes.count(node)) continue;
      int mat = -1;
      std::string lay;
      std::string why = member_problem(s, node, mat, lay);
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
    std::vector<std::pair<std::pair<int, std::string>, std::vector<int>>> out;
    for (const auto& key : bucket_order) out.emplace_back(key, buckets[key]);
    return out;
  }

  // Grows a group from candidate `i` of one bucket: each later candidate that conflicts with
  // nothing joins it. Returns the members, the refusals in `refused`.
  std::vector<int> grow_group(const std::vector<int>& cand, std::size_t i, int id, std::vector<bool>& taken,
                              std::vector<std::string>& refused) {
    std::vector<int> members{cand[i]};
    assign(cand[i], id);
    for (std::size_t j = i + 1; j < cand.size(); ++j) {
      if (taken[j]) continue;
      if (!joining_pays(members, cand[j])) {
        refused.push_back("\"" + s.nodes[static_cast<std::size_t>(cand[j])].name + "\" left out: transforming its vertices when it moves costs more than its draw");
        continue;
      }
      assign(cand[j], id);
      auto c = conflicts({id});
      if (c.empty()) {
        members.push_back(cand[j]);
        taken[j] = true;
      } else {
        assign(cand[j], kSingle);
        refused.push_back("\"" + s.nodes[static_cast<std::size_t>(cand[j])].name + "\" left out: " + c.front());
      }
    }
    taken[i] = true;
    return members;
  }

  // --propose-groups: merges the ungrouped objects greedily, bucket by bucket, recording a
  // decision for every group tried. Proposed groups get ids from `first_id` on.
  void propose(int first_id) {
    int next_id = first_id;
    for (const auto& [key, cand] : candidate_buckets()) {
      const std::string mat_name = material_name(key.first);
      std::vector<bool> taken(cand.size(), false);
      for (std::size_t i = 0; i < cand.size(); ++i) {
        if (taken[i]) continue;
        const int id = next_id;
        std::vector<std::string> refused;
        const std::vector<int> members = grow_group(cand, i, id, taken, refused);
        GroupDecision dec;
        for (int m : members) dec.members.push_back(s.nodes[static_cast<std::size_t>(m)].name);
        // Decided before any later group is checked against this one, so undoing it is safe.
        const std::optional<MergePrediction> cost = members.size() < 2 ? std::nullopt : predict(members);
        if (cost && !cost->pays()) {
          for (int m : members) assign(m, kSingle);
          dec.group = "(not merged)";
          dec.reasons.push_back(describe(*cost));
        } else if (members.size() < 2) {
          assign(cand[i], kSingle);
          dec.group = "(not proposed)";
          dec.reasons.push_back("no other object with material \"" + mat_name + "\" can join it without overlap or an order change");
        } else {
          dec.group = "auto_" + std::to_string(next_id - first_id) + "_" + mat_name;
          dec.accepted = true;
          unit_name[id] = dec.group;
          dec.reasons.push_back("same material \"" + mat_name + "\" (blend " + (ext[static_cast<std::size_t>(node_draws[cand[i]][0])].blend ? "on" : "off") +
                                "), same vertex layout, no overlap / order change over the animation ranges");
          if (cost) dec.reasons.push_back(describe(*cost));
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
  ConcatPlan finish() {
    std::map<int, std::vector<int>> by_unit;
    for (int d = 0; d < draw_count(); ++d) {
      const int u = unit[static_cast<std::size_t>(d)];
      if (u < kSingle && ext[static_cast<std::size_t>(d)].primitive == 0) by_unit[u].push_back(ext[static_cast<std::size_t>(d)].node);
    }
    for (const auto& [u, nodes] : by_unit) {
      Group g;
      g.name = unit_name.at(u);
      for (int node : nodes) g.members.push_back(s.nodes[static_cast<std::size_t>(node)].name);
      plan.groups.push_back(std::move(g));
    }
    return std::move(plan);
  }
};

}  // namespace

ConcatPlan plan_groups(const Scene& s, const std::vector<Group>& configured, bool propose, const std::string& origin,
                       const ConcatenationCosts* costs) {
  Planner pl(s, costs);
  for (std::size_t g = 0; g < configured.size(); ++g) pl.accept_configured(static_cast<int>(g), configured[g], origin);
  if (propose) pl.propose(static_cast<int>(configured.size()));
  return pl.finish();
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

}  // namespace meter::convert
