// The data converter's pipeline: glTF -> Scene with generated programs. Three phases:
//   1. load with tinygltf (syntax, buffers, image decoding);
//   2. validate every element, used or not, collecting all errors (and repairing the few problems
//      that have one obviously right answer, reported as warnings);
//   3. convert the elements of the default scene into the scene model, one stage per file, then
//      plan the mesh concatenation groups and generate the programs.
#include <sstream>

#include "convert_context.hpp"
#include "meter/convert/flat_geometry.hpp"
#include "meter/convert/scene_font.hpp"

namespace meter::convert {

ConvertError::ConvertError(const std::string& file, std::vector<Diagnostic> errs)
    : SceneError([&] {
        std::ostringstream os;
        os << file << ": " << errs.size() << (errs.size() == 1 ? " error" : " errors");
        std::size_t shown = 0;
        for (const auto& e : errs) {
          if (++shown > 50) {
            os << "\n  ... " << errs.size() - 50 << " more";
            break;
          }
          os << "\n  " << e.path << ": " << e.message;
        }
        return os.str();
      }()),
      errors(std::move(errs)) {}

namespace {

Scene build_scene(ConvertContext& ctx) {
  Scene s;
  s.source_name = ctx.file;
  s.config = ctx.cfg;
  s.ambient = glm::vec3(ctx.cfg.ambient[0], ctx.cfg.ambient[1], ctx.cfg.ambient[2]);
  // Textures are decoded RGBA8; the materials decide which are colour (sRGB).
  std::vector<int> texture_srgb(ctx.m.textures.size(), -1);
  const int default_material = convert_materials(ctx, s, texture_srgb);
  convert_textures(ctx, texture_srgb, s);
  convert_environment(ctx, s);
  convert_meshes(ctx, default_material, s);
  convert_cameras(ctx, s);
  convert_lights(ctx, s);
  convert_skins(ctx, s);
  convert_nodes(ctx, s);
  convert_animations(ctx, s);
  resolve_config(s, ctx.cfg, ctx.file);
  // The texts' font travels in the package: a missing one is a conversion error, not the view's.
  s.font = load_scene_font(ctx.cfg);
  // Groups are checked before programs exist: members need the vertex_alpha variant.
  ctx.plan = plan_groups(s, ctx.cfg.groups, ctx.opt.propose_groups, ctx.file, ctx.opt.merge_costs ? &*ctx.opt.merge_costs : nullptr);
  for (const auto& g : ctx.plan.groups) {
    for (const auto& m : g.members) ctx.group_members.insert(s.find_node(m));
  }
  generate_programs(ctx, s);
  attach_groups(s, ctx.plan);
  // Materials shaded Flat at full quality draw their faces' provoking vertices (levels add theirs).
  prepare_flat_draws(s);
  return s;
}

}  // namespace

ConvertResult convert_gltf(const std::string& path, const SceneConfig& config, const ConvertOptions& options) {
  const tinygltf::Model model = load_gltf(path);
  ConvertContext ctx(model, path, config, options);
  validate_gltf(ctx);
  if (!ctx.errors.empty()) {
    ConvertError e(ctx.file, ctx.errors);
    e.repairs = ctx.repairs;
    throw e;
  }
  ConvertResult r;
  r.scene = build_scene(ctx);
  r.repairs = ctx.repairs;
  r.concat_report = concat_report(ctx.plan);
  return r;
}

}  // namespace meter::convert
