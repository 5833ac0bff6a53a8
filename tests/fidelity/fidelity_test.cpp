// Fidelity and quality-ladder tests:
//  - each feature scene against its Blender reference stays above a measured floor (regression
//    bound on the engine's fidelity, see kFloors);
//  - the C++ PSNR (meter::platform::psnr) agrees with an independent tool, ImageMagick's
//    `compare -metric PSNR`, on a real engine render against its Blender reference (the platform
//    tests do this on generated images; here the input is what meter-bench fidelity measures);
//  - "preview equals target": each feature scene and the cluster, converted and drawn the product
//    way (optimized programs, MSAA 4), give >= 50 dB between OSMesa (the desktop preview) and EGL
//    (the target path). tests/shader-optimizer checks EGL vs OSMesa at 40 dB for its own question
//    (optimizer on/off); this is the stricter preview contract, on the packaged defaults.
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/convert/converter.hpp"
#include "meter/config/scene_config_parser.hpp"
#include "meter/convert/quality_ladder.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/backend.hpp"
#include "meter/platform/image.hpp"
#include "bound_signals.hpp"
#include "reference_state.hpp"

namespace {

using namespace meter;
namespace fs = std::filesystem;

// 50 dB = RMS error 0.8 levels: the bar for "what the preview shows is what the target shows".
constexpr double kPreviewEqualsTargetDb = 50.0;

struct SceneFiles {
  std::string name, glb, config;
};
void PrintTo(const SceneFiles& s, std::ostream* os) { *os << s.name; }

std::vector<SceneFiles> all_scenes() {
  const fs::path root = fs::path(METER_SOURCE_DIR) / "scenes";
  std::vector<SceneFiles> s;
  for (const char* f : {"ambient", "diffuse", "specular", "shininess", "emission", "bump", "reflection", "envmap2d", "skinning",
                        "morphing", "spot", "omni", "shadow"})
    s.push_back({f, (root / "features" / f / (std::string(f) + ".glb")).string(), (root / "features" / f / "scene.json").string()});
  s.push_back({"cluster", (root / "cluster/cluster.glb").string(), (root / "cluster/cluster.scene.json").string()});
  return s;
}

engine::Scene convert(const SceneFiles& s) {
  // As shipped, concatenation groups included (merged == unmerged: concat_render_test).
  const engine::SceneConfig c = meter::config::load_scene_config(s.config);
  return convert::convert_gltf(s.glb, c, convert::ConvertOptions{}).scene;
}

// Every bound signal at 60 % of its range, visibility/emissive on, text set: needles, lamps and the
// text overlay all appear in the compared frame.
engine::BindingOutputs state(const engine::Scene& scene) {
  engine::BindingEvaluator ev(scene);
  ev.update(meter::testing::bound_signals_at(scene.config, 0.6), true, -1.0);
  return ev.outputs();
}

// One backend alive at a time (two Mesa front ends in one process share libglapi state; see
// tests/shader-optimizer).
platform::Image render(platform::BackendKind kind, const engine::Scene& scene, const engine::BindingOutputs& st) {
  auto backend = platform::create_backend(kind);
  engine::Renderer r(*backend, scene, engine::RendererOptions{});
  r.apply(st);
  r.render(true, true);
  return r.last_image();
}

fs::path out_dir() {
  const fs::path d = fs::path(METER_BINARY_DIR) / "tests/fidelity/out";
  fs::create_directories(d);
  return d;
}

std::string run(const std::string& cmd) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return out;
  std::array<char, 256> buf{};
  while (fgets(buf.data(), int(buf.size()), p)) out += buf.data();
  pclose(p);
  return out;
}

TEST(Fidelity, PsnrAgreesWithImageMagickOnARealRender) {
  const SceneFiles s = all_scenes()[2];  // specular: a lit teapot with highlights, not a flat image
  const engine::Scene scene = convert(s);
  const platform::Image img = render(platform::BackendKind::Egl, scene, state(scene));
  const fs::path ref_file = fs::path(s.glb).parent_path() / "reference.png";
  const platform::Image ref = platform::read_png(ref_file);
  const fs::path img_file = out_dir() / "specular.egl.png";
  platform::write_png(img, img_file);

  const double ours = platform::psnr(img, ref);
  // compare prints "<dB> (<normalised>)" on stderr; exit status 1 just means "images differ".
  const std::string printed = run("compare -metric PSNR '" + img_file.string() + "' '" + ref_file.string() + "' null: 2>&1");
  ASSERT_FALSE(printed.empty()) << "ImageMagick 'compare' printed nothing (package imagemagick)";
  double theirs = 0.0;
  ASSERT_EQ(std::sscanf(printed.c_str(), "%lf", &theirs), 1) << "compare printed: " << printed;
  std::printf("specular: meter psnr %.4f dB, ImageMagick %.4f dB\n", ours, theirs);
  // A real render and the reference differ (finite PSNR in the range the fidelity table reports),
  // so the agreement below compares two non-trivial numbers.
  EXPECT_GT(ours, 20.0);
  EXPECT_LT(ours, 60.0);
  EXPECT_NEAR(ours, theirs, 0.01) << "compare printed: " << printed;

  // The masked variant by its definition: selecting every pixel gives the full-frame value.
  platform::Mask all{img.width, img.height, std::vector<std::uint8_t>(std::size_t(img.width) * img.height, 1)};
  EXPECT_DOUBLE_EQ(platform::psnr_masked(img, ref, all), ours);
}

class PreviewEqualsTarget : public ::testing::TestWithParam<SceneFiles> {};

TEST_P(PreviewEqualsTarget, OsmesaAndEglAgreeTo50Db) {
  const SceneFiles& s = GetParam();
  const engine::Scene scene = convert(s);
  const auto st = state(scene);
  const platform::Image egl = render(platform::BackendKind::Egl, scene, st);
  const platform::Image osmesa = render(platform::BackendKind::OSMesa, scene, st);
  platform::write_png(egl, out_dir() / (s.name + ".egl.png"));
  platform::write_png(osmesa, out_dir() / (s.name + ".osmesa.png"));
  // Not two empty clears: the frame has content (the teapot covers ~20 % of the feature frames).
  const auto* bg = egl.pixel(0, 0);
  const double share = double(platform::object_mask(egl, {bg[0], bg[1], bg[2]}, 8).count()) / (double(egl.width) * egl.height);
  EXPECT_GT(share, 0.02) << s.name << ": the EGL frame is (nearly) empty";
  const double db = platform::psnr(egl, osmesa);
  std::printf("%-10s EGL vs OSMesa %s dB (content %.1f %%)\n", s.name.c_str(), std::isinf(db) ? "identical" : std::to_string(db).c_str(),
              100.0 * share);
  EXPECT_GE(db, kPreviewEqualsTargetDb) << s.name << " (frames in " << out_dir().string() << ")";
}

INSTANTIATE_TEST_SUITE_P(Scenes, PreviewEqualsTarget, ::testing::ValuesIn(all_scenes()),
                         [](const auto& info) { return info.param.name; });

// Fidelity against the authoring tool: each feature scene and the cluster (in the state of its
// Blender preview, tests/support/reference_state.hpp), drawn the product way, keeps its PSNR
// over object pixels (the reference's pixels more than 8 levels from its background, as
// meter-bench fidelity counts them) against the Blender reference above a floor. Floor = the value
// measured on 2026-12-02 (skinning, bump, shadow: 2026-12-04; cluster, reflection, envmap2d: 2026-12-05) (docs/fidelity.md) minus 0.5 dB: EGL and OSMesa give identical frames and
// a Mesa rasteriser change moves a few edge pixels (< 0.1 dB here), while every fix behind these
// numbers is worth more than 0.7 dB: environment map off (reflection -16 dB, envmap2d -11 dB), the
// glTF spot curve instead of Blender's (spot -13 dB), diffuse scaled by (1 - F) again (-1.2 to
// -2.4 dB on the lit dielectrics), the image's own box-filtered mips instead of the prefiltered
// reflection probe (reflection -1.9 dB, envmap2d -0.8 dB), the mirror shaded per pixel instead of
// per MSAA sample (reflection -4.0 dB), the box resolve instead of the scenes' film filter
// (-0.8 dB reflection ... -9.9 dB emission), skinned normals carried by the blended joint matrix
// instead of recomputed from the deformed surface (skinning -11.5 dB), trilinear texture filtering
// instead of EEVEE's 2x anisotropic (bump -1.6 dB), normal-mapped materials shaded per pixel
// instead of per MSAA sample (bump -0.65 dB), no shadow maps (shadow -13.8 dB), the cluster's box resolve
// (-3.3 dB), the cluster's 8-bit samples instead of half floats (-3.0 dB).
struct Floor {
  const char* scene;
  double object_db;  // measured object PSNR - 0.5 dB
};
void PrintTo(const Floor& f, std::ostream* os) { *os << f.scene; }
constexpr Floor kFloors[] = {
    {"ambient", 42.9},   {"diffuse", 39.9},  {"specular", 38.7},   {"shininess", 36.7},
    {"emission", 42.2},  {"bump", 34.9},     {"reflection", 37.0}, {"envmap2d", 43.2},
    {"skinning", 44.0},  {"morphing", 40.1}, {"spot", 47.0},       {"omni", 43.7},
    {"shadow", 38.9},    {"cluster", 30.8},
};

class AgainstBlender : public ::testing::TestWithParam<Floor> {};

SceneFiles scene_named(const std::string& name) {
  for (const auto& c : all_scenes())
    if (c.name == name) return c;
  throw std::runtime_error("no scene " + name);
}

// PSNR over the reference's object pixels (more than 8 levels from its background, as meter-bench
// fidelity counts them) of `scene` (the files `s`, maybe at another ladder point) drawn on EGL in
// the state its Blender reference shows, against that reference.
double object_db_against_blender(const SceneFiles& s, const engine::Scene& scene) {
  const bool cluster = s.name == "cluster";
  const platform::Image img = render(platform::BackendKind::Egl, scene,
                                     cluster ? meter::testing::cluster_reference_state(scene)
                                             : meter::testing::feature_reference_state(scene));
  const fs::path ref_file = fs::path(s.glb).parent_path() / (cluster ? "preview-blender.png" : "reference.png");
  const platform::Image ref = platform::read_png(ref_file);
  if (img.width != ref.width || img.height != ref.height)
    throw std::runtime_error(ref_file.string() + " is " + std::to_string(ref.width) + "x" + std::to_string(ref.height) +
                             ", the render " + std::to_string(img.width) + "x" + std::to_string(img.height));
  const auto* bg = ref.pixel(0, 0);
  const platform::Mask mask = platform::object_mask(ref, {bg[0], bg[1], bg[2]}, 8);
  if (mask.count() == 0) throw std::runtime_error(ref_file.string() + " has no object pixels");
  return platform::psnr_masked(img, ref, mask);
}

TEST_P(AgainstBlender, ObjectPsnrStaysAboveTheMeasuredFloor) {
  const Floor f = GetParam();
  const SceneFiles s = scene_named(f.scene);
  const double db = object_db_against_blender(s, convert(s));
  std::printf("%-10s object PSNR vs Blender %.2f dB (floor %.1f)\n", f.scene, db, f.object_db);
  EXPECT_GE(db, f.object_db) << f.scene << ": fell below its measured floor (docs/fidelity.md)";
}

INSTANTIATE_TEST_SUITE_P(Scenes, AgainstBlender, ::testing::ValuesIn(kFloors),
                         [](const auto& info) { return std::string(info.param.scene); });

// Per-sample shading touches only the draws that call for it: the normal-mapped bump teapot and
// the chrome (roughness 0.05) reflection teapot are drawn differently with the scene's
// "sample_shading" on and off; the diffuse teapot (no normal map, no environment) and the rough
// (0.5) envmap2d teapot byte for byte the same; on both backends. The quality key reaches the config.
TEST(Fidelity, SampleShadingChangesOnlyNormalMappedAndMirrorDraws) {
  EXPECT_EQ(convert::describe_quality(convert::parse_quality("sample_shading=off")), "sample_shading=off");
  EXPECT_EQ(convert::describe_quality(convert::parse_quality("sample_shading=normal-maps+mirrors")),
            "sample_shading=normal-maps+mirrors");
  EXPECT_THROW(convert::parse_quality("sample_shading=all"), engine::SceneError);
  for (const auto kind : {platform::BackendKind::Egl, platform::BackendKind::OSMesa}) {
    for (const std::string name : {"bump", "reflection", "diffuse", "envmap2d"}) {
      SceneFiles s;
      for (const auto& c : all_scenes())
        if (c.name == name) s = c;
      const engine::Scene on = convert(s);
      ASSERT_TRUE(on.config.sample_shading.normal_maps && on.config.sample_shading.mirrors) << name;
      engine::Scene off = on;
      convert::apply_quality(off, convert::parse_quality("sample_shading=off"));
      ASSERT_FALSE(off.config.sample_shading.any());
      const platform::Image a = render(kind, on, state(on)), b = render(kind, off, state(off));
      const double db = platform::psnr(a, b);
      std::printf("%-10s %-7s per sample vs per pixel: %.2f dB\n", name.c_str(), kind == platform::BackendKind::Egl ? "egl" : "osmesa", db);
      if (name == "bump" || name == "reflection") {
        EXPECT_LT(db, 60.0) << name << ": per-sample shading did not change the draw that calls for it";
      } else {
        EXPECT_EQ(a.rgba, b.rgba) << name << ": per-sample shading changed a draw without a normal map or a mirror";
      }
    }
  }
}

// The 50 dB bar can fail: a one-step quality change on the same backend (MSAA 4 -> 1: edges only)
// already falls under it, so two backends that disagreed on edges or shading would be caught.
TEST(Fidelity, FiftyDbDetectsAnEdgeOnlyChange) {
  const SceneFiles s = all_scenes()[2];
  const engine::Scene scene = convert(s);
  const auto st = state(scene);
  auto backend = platform::create_backend(platform::BackendKind::Egl);
  engine::RendererOptions o4, o1;
  o1.msaa = 1;
  engine::Renderer r4(*backend, scene, o4), r1(*backend, scene, o1);
  r4.apply(st), r1.apply(st);
  r4.render(true, true), r1.render(true, true);
  EXPECT_LT(platform::psnr(r4.last_image(), r1.last_image()), kPreviewEqualsTargetDb);
}

// Quality ladder (meter/convert/quality_ladder.hpp): settings really change what is drawn, and bad input is named.
TEST(QualityLadder, EachStepChangesTheSceneAndBadInputIsNamed) {
  const SceneFiles s = all_scenes()[2];
  const engine::Scene base = convert(s);
  engine::Scene g = base;
  const auto rep = convert::apply_quality(g, convert::parse_quality("shading=gouraud,precision=mediump,lod=0.5"));
  EXPECT_GE(rep.programs_regenerated, 1);
  for (const auto& d : g.draws) {
    EXPECT_EQ(g.programs[std::size_t(d.program)].program.features.shading, bridge::ShadingModel::Gouraud);
    EXPECT_EQ(g.programs[std::size_t(d.program)].program.features.precision, bridge::Precision::Mediump);
  }
  EXPECT_GT(rep.primitives_simplified, 0);
  EXPECT_LE(rep.triangles_after, rep.triangles_before * 6 / 10);
  EXPECT_GT(rep.triangles_after, rep.triangles_before * 3 / 10);

  // Per object: only the named node changes.
  engine::Scene p = base;
  const std::string node = p.nodes[std::size_t(p.draws.front().node)].name;
  convert::QualitySettings q;
  q.objects[node].shading = bridge::ShadingModel::Unlit;
  convert::apply_quality(p, q);
  EXPECT_EQ(p.programs[std::size_t(p.draws.front().program)].program.features.shading, bridge::ShadingModel::Unlit);

  engine::Scene bad = base;
  convert::QualitySettings unknown;
  unknown.objects["NoSuchNode"].lod = 0.5f;
  EXPECT_THROW(convert::apply_quality(bad, unknown), engine::SceneError);
  EXPECT_THROW(convert::parse_quality("lod=0"), engine::SceneError);
  EXPECT_THROW(convert::parse_quality("msaa=3"), engine::SceneError);
  EXPECT_THROW(convert::parse_quality("filter=aniso"), engine::SceneError);
  EXPECT_EQ(convert::parse_quality("msaa=8").msaa, 8);
  // Anisotropic: trilinear sampling plus a 16x anisotropy degree on every texture (bump: the
  // scene with a normal map, so there are textures to change).
  engine::Scene a = convert(all_scenes()[5]);
  ASSERT_FALSE(a.textures.empty());
  // Unset, the textures are sampled as EEVEE samples them: 2x anisotropy.
  for (const auto& t : a.textures) EXPECT_EQ(t.max_anisotropy, 2.0f);
  convert::apply_quality(a, convert::parse_quality("filter=anisotropic"));
  for (const auto& t : a.textures) EXPECT_EQ(t.max_anisotropy, 16.0f);
  convert::apply_quality(a, convert::parse_quality("filter=trilinear"));
  for (const auto& t : a.textures) EXPECT_EQ(t.max_anisotropy, 1.0f);
  EXPECT_THROW(convert::parse_quality("shading=phong"), engine::SceneError);
  EXPECT_THROW(convert::parse_quality("speed"), engine::SceneError);
  EXPECT_EQ(convert::describe_quality(convert::parse_quality("msaa=2,shading=flat")), "shading=flat,msaa=2");
  EXPECT_THROW(convert::parse_quality("environment=maybe"), engine::SceneError);
}

// Affine interpolation (NV_shader_noperspective_interpolation): every program compiles on both
// backends, and the textured teapot of the bump scene changes (its normal map slides across
// foreshortened faces) but stays the same picture.
TEST(QualityLadder, AffineInterpolationCompilesOnBothBackendsAndChangesTexturing) {
  const engine::Scene base = convert(all_scenes()[5]);  // bump
  engine::Scene affine = base;
  const auto rep = convert::apply_quality(affine, convert::parse_quality("interpolation=affine"));
  EXPECT_EQ(rep.programs_made_affine, static_cast<int>(affine.programs.size()));
  EXPECT_NE(affine.programs.front().program.fragment_source.find("noperspective in"), std::string::npos);
  EXPECT_EQ(convert::describe_quality(convert::parse_quality("interpolation=affine")), "interpolation=affine");
  EXPECT_THROW(convert::parse_quality("interpolation=linear"), engine::SceneError);
  for (auto kind : {platform::BackendKind::Egl, platform::BackendKind::OSMesa}) {
    const platform::Image a = render(kind, base, state(base));
    const platform::Image b = render(kind, affine, state(affine));
    const double db = platform::psnr(a, b);
    std::printf("[ affine   ] bump %s: affine vs perspective %.1f dB\n", std::string(platform::to_string(kind)).c_str(), db);
    // Measured 50.2 dB on both: the teapot is small on screen and its faces are nearly
    // screen-parallel, so only the texture (normal map) coordinates shift, by a fraction of a texel
    // over most faces. Bounds: equal images (inf) would mean the qualifier had no effect; under 25 dB
    // would mean something other than interpolation changed.
    EXPECT_LT(db, 80.0);
    EXPECT_GT(db, 25.0);
  }
}

// The environment rung: a scene with a map loses it (every program regenerated without the
// sampler), models without per-pixel normals drop it instead of failing, a scene without one is
// untouched.
TEST(QualityLadder, EnvironmentOffAndCheaperModelsDropTheMap) {
  const SceneFiles refl = all_scenes()[6];
  ASSERT_EQ(refl.name, "reflection");
  const engine::Scene base = convert(refl);
  ASSERT_TRUE(base.environment.present());
  auto any_env = [](const engine::Scene& s) {
    for (const auto& d : s.draws)
      if (s.programs[std::size_t(d.program)].program.features.environment_map_2d) return true;
    return false;
  };
  EXPECT_TRUE(any_env(base));
  engine::Scene off = base;
  const auto rep = convert::apply_quality(off, convert::parse_quality("environment=off"));
  EXPECT_TRUE(rep.environment_dropped);
  EXPECT_FALSE(off.environment.present());
  EXPECT_FALSE(any_env(off));
  EXPECT_EQ(convert::describe_quality(convert::parse_quality("environment=off")), "environment=off");
  engine::Scene gouraud = base;
  EXPECT_NO_THROW(convert::apply_quality(gouraud, convert::parse_quality("shading=gouraud")));
  EXPECT_FALSE(any_env(gouraud));
  engine::Scene plain = convert(all_scenes()[2]);
  EXPECT_FALSE(convert::apply_quality(plain, convert::parse_quality("environment=off")).environment_dropped);
}

// The resolve settings as ladder points: each key round-trips, a bad value is refused, the
// scene's own setting leaves its config as it is and the other one changes it, and the setting
// the scene's Blender render is closer to scores higher by a margin. Measured on 2026-12-02 /
// 2026-12-04: emission object PSNR 42.75 dB with the film filter, 32.87 dB with the box (margin 3);
// the cluster 31.29 dB with half-float samples, 28.27 dB with 8-bit ones (margin 2). Each margin is
// far inside its gap and far above run-to-run noise (frames are deterministic).
struct ResolvePoint {
  const char* scene;
  const char* closer;   // the quality string closer to Blender
  const char* further;  // the one further from it
  bool closer_is_own;   // whether `closer` is what the scene's config asks for
  const char* bad;      // a value the key refuses
  double margin_db;
};
void PrintTo(const ResolvePoint& p, std::ostream* os) { *os << p.closer; }
constexpr ResolvePoint kResolvePoints[] = {
    {"emission", "resolve=blackman-harris", "resolve=box", true, "resolve=gauss", 3.0},
    {"cluster", "sample_format=rgba16f", "sample_format=srgb8", true, "sample_format=rgba32f", 2.0},
};

class ResolveLadderPoint : public ::testing::TestWithParam<ResolvePoint> {};

TEST_P(ResolveLadderPoint, KeySetsTheConfigAndBlendersSettingIsCloser) {
  const ResolvePoint p = GetParam();
  for (const char* q : {p.closer, p.further}) EXPECT_EQ(convert::describe_quality(convert::parse_quality(q)), q);
  EXPECT_THROW(convert::parse_quality(p.bad), engine::SceneError);
  const SceneFiles s = scene_named(p.scene);
  const engine::Scene own = convert(s);
  engine::Scene closer = own, further = own;
  convert::apply_quality(closer, convert::parse_quality(p.closer));
  convert::apply_quality(further, convert::parse_quality(p.further));
  EXPECT_EQ(closer.config.resolve == own.config.resolve, p.closer_is_own) << p.closer << " against the scene's config";
  EXPECT_EQ(further.config.resolve == own.config.resolve, !p.closer_is_own) << p.further << " against the scene's config";
  const double closer_db = object_db_against_blender(s, closer), further_db = object_db_against_blender(s, further);
  std::printf("%s object PSNR: %s %.2f dB, %s %.2f dB\n", p.scene, p.closer, closer_db, p.further, further_db);
  EXPECT_GT(closer_db, further_db + p.margin_db);
}

INSTANTIATE_TEST_SUITE_P(Keys, ResolveLadderPoint, ::testing::ValuesIn(kResolvePoints),
                         [](const auto& info) { return std::string(info.param.scene); });

}  // namespace
