#include "gl/gpu_scene.hpp"

#include <algorithm>
#include <chrono>
#include <map>

#include "meter/engine/gl/program_binary_cache.hpp"
#include "meter/engine/gl/texture_mips.hpp"
#include "meter/engine/merged_draws.hpp"
#include "meter/engine/renderer.hpp"

namespace meter::engine {

using bridge::AttributeSemantic;
using bridge::UniformSemantic;

namespace {
bool is_light_semantic(UniformSemantic s) {
  return s == UniformSemantic::LightColor || s == UniformSemantic::LightIntensity || s == UniformSemantic::LightPosition ||
         s == UniformSemantic::LightDirection || s == UniformSemantic::LightRange ||
         s == UniformSemantic::LightInnerConeCos || s == UniformSemantic::LightOuterConeCos;
}
bool reads_normals(const bridge::Program& p) {
  return std::any_of(p.attributes.begin(), p.attributes.end(), [](const auto& a) { return a.semantic == AttributeSemantic::Normal; });
}
}  // namespace

GpuScene::GpuScene(const platform::Gl& gl, const Scene& scene, const bridge::Program* uber_shader, bool merged,
                   platform::ProgramCache* programs, ProgramBinaryCache* binaries)
    : gl_(gl), program_cache_(programs), binaries_(binaries), scene_(scene) {
  // Programs: the package's generated ones, or (benchmark baseline) the uber-shader alone.
  if (uber_shader) {
    if (!uber_shader->uber) throw SceneError("RendererOptions::uber_shader is not an uber-shader program");
    add_program(*uber_shader, scene_.source_name + " uber-shader", true);
  } else {
    // Programs only a cheaper level uses are compiled when a frame first needs them (prepare()):
    // a scene drawn at full quality compiles what it did before levels existed.
    std::vector<char> used(scene_.programs.size(), 0);
    for (const auto& d : scene_.draws) used[static_cast<std::size_t>(d.program)] = 1;
    for (std::size_t i = 0; i < scene_.programs.size(); ++i)
      add_program(scene_.programs[i].program, scene_.source_name + " program " + std::to_string(i), used[i] != 0);
  }
  upload_textures();
  build_draws(uber_shader != nullptr);
  if (merged) build_groups();
  platform::check_gl(gl_, scene_.source_name + ": uploading the scene");
}

GpuScene::~GpuScene() {
  for (auto& d : draws_)
    for (auto& sh : d->shadings) gl_.DeleteVertexArrays(1, &sh.input.vao);
  for (auto& g : groups_) {
    for (auto& in : g->inputs) gl_.DeleteVertexArrays(1, &in.vao);
    gl_.DeleteBuffers(1, &g->vbo);
    gl_.DeleteBuffers(1, &g->ebo);
  }
  if (!buffers_.empty()) gl_.DeleteBuffers(static_cast<GLsizei>(buffers_.size()), buffers_.data());
  if (!textures_.empty()) gl_.DeleteTextures(static_cast<GLsizei>(textures_.size()), textures_.data());
  if (white_texture_) gl_.DeleteTextures(1, &white_texture_);
  if (environment_probe_) gl_.DeleteTextures(1, &environment_probe_);
  for (auto& p : programs_) platform::release_program(program_cache_, gl_, p->program);
  for (auto& [_, p] : depth_programs_) platform::release_program(program_cache_, gl_, p->program);
}

void GpuScene::add_program(const bridge::Program& p, const std::string& label, bool compile_now) {
  auto gp = std::make_unique<GpuProgram>();
  gp->info = &p;
  gp->label = label;
  if (compile_now) compile(*gp);
  programs_.push_back(std::move(gp));
}

void GpuScene::prepare(const FrameState& frame) {
  for (std::size_t i = 0; i < draws_.size() && i < frame.draws.size(); ++i) {
    const auto level = static_cast<std::size_t>(frame.draws[i].shading);
    if (level < draws_[i]->shadings.size() && !draws_[i]->shadings[level].program->program)
      compile(*draws_[i]->shadings[level].program);
  }
}

void GpuScene::prepare_depth(const FrameState& frame) {
  for (std::size_t i = 0; i < draws_.size() && i < frame.draws.size(); ++i) {
    const auto level = std::min(static_cast<std::size_t>(frame.draws[i].shading), draws_[i]->shadings.size() - 1);
    const GpuProgram* own = draws_[i]->shadings[level].program;
    if (depth_programs_.count(own)) continue;
    auto gp = std::make_unique<GpuProgram>();
    gp->info = own->info;
    gp->label = own->label + " (shadow map depth)";
    // Writes depth only: no outputs, so the driver runs no shading for the map's texels. Same
    // #version line as the vertex shader (GLSL ES 3.00 from a package, desktop GLSL from
    // to_desktop_glsl): stages of different languages do not link.
    const std::string& vs = own->info->vertex_source;
    compile(*gp, vs.substr(0, vs.find('\n') + 1) + "void main() {}\n");
    depth_programs_.emplace(own, std::move(gp));
  }
}

const GpuProgram* GpuScene::depth_program(const GpuProgram* program) const {
  const auto it = depth_programs_.find(program);
  return it == depth_programs_.end() ? nullptr : it->second.get();
}

void GpuScene::compile(GpuProgram& program, const std::string& fragment_source) {
  GpuProgram* gp = &program;
  const bridge::Program& p = *gp->info;
  const std::string& fragment = fragment_source.empty() ? p.fragment_source : fragment_source;
  const auto began = std::chrono::steady_clock::now();
  gp->program = binaries_ && !program_cache_ ? binaries_->link(gl_, p.vertex_source, fragment, gp->label)
                                             : platform::acquire_program(program_cache_, gl_, p.vertex_source, fragment, gp->label);
  program_link_ms_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - began).count();
  ++programs_linked_;
  for (const auto& u : p.uniforms) {
    GpuProgram::Uniform gu;
    gu.semantic = u.semantic;
    if (is_light_semantic(u.semantic) && u.array_size > 1) {
      // The uber-shader's light arrays: one location per element, each set like a single light.
      for (int k = 0; k < u.array_size; ++k) {
        gu.location = gl_.GetUniformLocation(gp->program, (u.name + "[" + std::to_string(k) + "]").c_str());
        gu.index = u.index + k;
        if (gu.location >= 0) gp->uniforms.push_back(gu);
      }
      continue;
    }
    gu.location = gl_.GetUniformLocation(gp->program, u.name.c_str());
    gu.index = u.index;
    gu.array_size = u.array_size;
    if (gu.location >= 0) gp->uniforms.push_back(gu);  // the driver may drop unused uniforms
  }
  for (const auto& s : p.samplers) {
    GpuProgram::Sampler gs{gl_.GetUniformLocation(gp->program, s.name.c_str()), s.slot, s.unit, s.index};
    if (gs.location >= 0) gp->samplers.push_back(gs);
  }
  platform::check_gl(gl_, gp->label + ": compiling");
}

void GpuScene::upload_textures() {
  for (std::size_t index = 0; index < scene_.textures.size(); ++index) {
    const Texture& t = scene_.textures[index];
    GLuint tex = 0;
    gl_.GenTextures(1, &tex);
    gl_.BindTexture(GL_TEXTURE_2D, tex);
    gl_.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl_.TexImage2D(GL_TEXTURE_2D, 0, t.srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8, t.width, t.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, t.rgba.data());
    const bool mip = t.min_filter == GL_NEAREST_MIPMAP_NEAREST || t.min_filter == GL_LINEAR_MIPMAP_NEAREST ||
                     t.min_filter == GL_NEAREST_MIPMAP_LINEAR || t.min_filter == GL_LINEAR_MIPMAP_LINEAR;
    if (mip && box_mips_apply(t.width, t.height, t.srgb)) {
      const auto levels = box_mip_chain(t.rgba, t.width, t.height);
      for (std::size_t k = 0; k < levels.size(); ++k) {
        const int level = static_cast<int>(k) + 1;
        gl_.TexImage2D(GL_TEXTURE_2D, level, GL_RGBA8, std::max(1, t.width >> level), std::max(1, t.height >> level), 0,
                       GL_RGBA, GL_UNSIGNED_BYTE, levels[k].data());
      }
    } else if (mip) {
      gl_.GenerateMipmap(GL_TEXTURE_2D);
    }
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, t.min_filter);
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, t.mag_filter);
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, t.wrap_s);
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, t.wrap_t);
    if (t.max_anisotropy > 1.0f) {
      // EXT_texture_filter_anisotropic (llvmpipe has it on both backends); without it the query
      // fails and the texture stays trilinear.
      constexpr GLenum kMaxAnisotropy = 0x84FE, kMaxSupported = 0x84FF;
      GLfloat supported = 1.0f;
      gl_.GetFloatv(kMaxSupported, &supported);
      if (gl_.GetError() == GL_NO_ERROR && supported > 1.0f)
        gl_.TexParameterf(GL_TEXTURE_2D, kMaxAnisotropy, std::min(t.max_anisotropy, supported));
    }
    textures_.push_back(tex);
  }
  upload_environment_probe();
  {
    const std::uint8_t white[4] = {255, 255, 255, 255};
    gl_.GenTextures(1, &white_texture_);
    gl_.BindTexture(GL_TEXTURE_2D, white_texture_);
    gl_.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, white);
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
}

// The reflection probe as a cube map with its prefiltered levels as the mip chain (read with
// textureLod at sqrt(roughness) * the last level; never anisotropic: each level is already the lobe).
void GpuScene::upload_environment_probe() {
  const bridge::EnvironmentProbe& probe = scene_.environment.probe;
  if (probe.levels <= 0) return;
  gl_.GenTextures(1, &environment_probe_);
  gl_.BindTexture(GL_TEXTURE_CUBE_MAP, environment_probe_);
  gl_.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  const std::uint8_t* texels = probe.rgb.data();
  for (int level = 0; level < probe.levels; ++level) {
    const int size = probe.face_size >> level;
    for (int face = 0; face < 6; ++face) {
      gl_.TexImage2D(static_cast<GLenum>(GL_TEXTURE_CUBE_MAP_POSITIVE_X + face), level, GL_SRGB8, size, size, 0, GL_RGB,
                     GL_UNSIGNED_BYTE, texels);
      texels += std::size_t(size) * std::size_t(size) * 3u;
    }
  }
  gl_.TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAX_LEVEL, probe.levels - 1);
  gl_.TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  gl_.TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  gl_.TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl_.TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  // GLES 3 filters across cube faces always; desktop GL only when asked (as Blender does).
  constexpr GLenum kTextureCubeMapSeamless = 0x884F;
  if (!gl_.info.is_gles) gl_.Enable(kTextureCubeMapSeamless);
}

GpuVertexInput GpuScene::vertex_input(const GpuProgram& program, const Primitive& layout, bool merged, GLuint vbo, GLuint ebo) {
  GpuVertexInput in;
  const int stride = merged ? merged_stride(layout) : layout.stride;
  gl_.GenVertexArrays(1, &in.vao);
  gl_.BindVertexArray(in.vao);
  gl_.BindBuffer(GL_ARRAY_BUFFER, vbo);
  gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo);
  for (const auto& a : program.info->attributes) {
    const auto loc = static_cast<GLuint>(a.location);
    int components = 0, offset = 0;
    if (merged && a.semantic == AttributeSemantic::VertexAlpha) {
      components = 1, offset = layout.stride;
    } else {
      auto it = std::find_if(layout.layout.begin(), layout.layout.end(), [&](const VertexAttribute& v) {
        return v.semantic == a.semantic && (v.index == a.index || (v.index < 0 && a.index < 0));
      });
      if (it == layout.layout.end()) {
        // Missing data gets the neutral value: white vertex colour, full vertex alpha, zero otherwise.
        glm::vec4 c(0.0f, 0.0f, 0.0f, 1.0f);
        if (a.semantic == AttributeSemantic::Color0 || a.semantic == AttributeSemantic::VertexAlpha) c = glm::vec4(1.0f);
        if (a.semantic == AttributeSemantic::Weights0) c = glm::vec4(1.0f, 0.0f, 0.0f, 0.0f);
        in.constant_attributes.emplace_back(loc, c);
        continue;
      }
      components = it->components, offset = it->offset;
    }
    gl_.EnableVertexAttribArray(loc);
    gl_.VertexAttribPointer(loc, components, GL_FLOAT, GL_FALSE, stride * static_cast<GLsizei>(sizeof(float)),
                            reinterpret_cast<const void*>(static_cast<std::uintptr_t>(offset) * sizeof(float)));
  }
  gl_.BindVertexArray(0);
  return in;
}

void GpuScene::build_draws(bool uber) {
  // Vertex/index buffers, one pair per primitive, shared by every draw of it. The index buffer
  // holds the full list, then each LOD level's.
  std::map<std::pair<int, int>, std::pair<GLuint, GLuint>> vbos;
  for (std::size_t di = 0; di < scene_.draws.size(); ++di) {
    const DrawItem& d = scene_.draws[di];
    const Primitive& prim = scene_.meshes[static_cast<std::size_t>(d.mesh)].primitives[static_cast<std::size_t>(d.primitive)];
    auto key = std::make_pair(d.mesh, d.primitive);
    auto gd = std::make_unique<GpuDraw>();
    gd->item = &d;
    gd->prim = &prim;
    std::size_t total = prim.indices.size();
    gd->lods.emplace_back(0, static_cast<GLsizei>(prim.indices.size()));
    for (const LodLevel& l : prim.lods) {
      gd->lods.emplace_back(total * sizeof(std::uint32_t), static_cast<GLsizei>(l.indices.size()));
      total += l.indices.size();
    }
    // Then the Flat lists, in the same order (the package reader checked they come on every level).
    if (!prim.flat_indices.empty()) {
      gd->flat_lods.emplace_back(total * sizeof(std::uint32_t), static_cast<GLsizei>(prim.flat_indices.size()));
      total += prim.flat_indices.size();
      for (const LodLevel& l : prim.lods) {
        gd->flat_lods.emplace_back(total * sizeof(std::uint32_t), static_cast<GLsizei>(l.flat_indices.size()));
        total += l.flat_indices.size();
      }
    }
    // A skinned primitive whose program reads normals gets a buffer per draw: its normals are
    // rewritten with the draw's pose.
    const bool skinned = scene_.nodes[static_cast<std::size_t>(d.node)].skin >= 0 && has_skinned_normals(prim) &&
                         reads_normals(scene_.programs[static_cast<std::size_t>(d.program)].program);
    if (skinned) key = {-1 - static_cast<int>(di), 0};
    if (!vbos.count(key)) {
      GLuint b[2];
      gl_.GenBuffers(2, b);
      gl_.BindBuffer(GL_ARRAY_BUFFER, b[0]);
      gl_.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(prim.vertices.size() * sizeof(float)), prim.vertices.data(),
                     skinned ? GL_DYNAMIC_DRAW : GL_STATIC_DRAW);
      gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, b[1]);
      gl_.BufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(total * sizeof(std::uint32_t)), nullptr, GL_STATIC_DRAW);
      gl_.BufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(prim.indices.size() * sizeof(std::uint32_t)), prim.indices.data());
      for (std::size_t k = 0; k < prim.lods.size(); ++k)
        gl_.BufferSubData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLintptr>(gd->lods[k + 1].first),
                          static_cast<GLsizeiptr>(prim.lods[k].indices.size() * sizeof(std::uint32_t)), prim.lods[k].indices.data());
      for (std::size_t k = 0; k < gd->flat_lods.size(); ++k) {
        const auto& list = k == 0 ? prim.flat_indices : prim.lods[k - 1].flat_indices;
        gl_.BufferSubData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLintptr>(gd->flat_lods[k].first),
                          static_cast<GLsizeiptr>(list.size() * sizeof(std::uint32_t)), list.data());
      }
      buffers_.insert(buffers_.end(), {b[0], b[1]});
      vbos[key] = {b[0], b[1]};
    }
    const auto [vbo, ebo] = vbos[key];
    if (skinned) skinned_.push_back({gd.get(), vbo, skinned_normals_layout(prim), prim.vertices, {}});
    GpuShading own;
    own.shape = &scene_.programs[static_cast<std::size_t>(d.program)].program;
    own.program = programs_[uber ? 0 : static_cast<std::size_t>(d.program)].get();
    own.input = vertex_input(*own.program, prim, false, vbo, ebo);
    own.flat_lists = own.shape->features.shading == ShadingModel::Flat && !gd->flat_lods.empty();
    gd->shadings.push_back(std::move(own));
    if (!uber && !scene_.draw_levels.empty()) {
      for (const ShadingLevel& l : scene_.draw_levels[di].shadings) {
        GpuShading sh;
        sh.shape = &scene_.programs[static_cast<std::size_t>(l.program)].program;
        sh.program = programs_[static_cast<std::size_t>(l.program)].get();
        sh.level = &l;
        sh.input = vertex_input(*sh.program, prim, false, vbo, ebo);
        sh.flat_lists = sh.shape->features.shading == ShadingModel::Flat && !gd->flat_lods.empty();
        gd->shadings.push_back(std::move(sh));
      }
    }
    draws_.push_back(std::move(gd));
  }
}

void GpuScene::update_skinned(const FrameState& frame, RendererStats& stats) {
  for (GpuSkinnedDraw& s : skinned_) {
    const auto node = static_cast<std::size_t>(s.draw->item->node);
    const Skin& skin = scene_.skins[static_cast<std::size_t>(scene_.nodes[node].skin)];
    std::vector<glm::mat4> joints = joint_matrices(skin, frame.world, frame.world[node]);
    if (joints == s.joints) continue;
    stats.skinned_normals_kept += skin_normals(*s.draw->prim, s.layout, joints, s.vertices);
    s.joints = std::move(joints);
    gl_.BindBuffer(GL_ARRAY_BUFFER, s.vbo);
    gl_.BufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(s.vertices.size() * sizeof(float)), s.vertices.data());
    ++stats.skinned_normal_updates;
  }
}

void GpuScene::build_groups() {
  for (const auto& mg : scene_.groups) {
    auto g = std::make_unique<GpuGroup>();
    std::uint32_t vertices = 0;
    for (int d : mg.draws) {
      GpuGroup::Member m;
      m.draw = draws_[static_cast<std::size_t>(d)].get();
      m.first_vertex = vertices;
      vertices += m.draw->prim->vertex_count;
      g->members.push_back(m);
    }
    GpuDraw* rep = draws_[static_cast<std::size_t>(mg.draws.front())].get();
    rep->group = g.get();
    const Primitive& layout = *rep->prim;
    g->vertices.assign(std::size_t(vertices) * std::size_t(merged_stride(layout)), 0.0f);
    GLuint b[2];
    gl_.GenBuffers(2, b);
    g->vbo = b[0], g->ebo = b[1];
    gl_.BindBuffer(GL_ARRAY_BUFFER, g->vbo);
    // DYNAMIC: rewritten (in member ranges) whenever a member moves.
    gl_.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(g->vertices.size() * sizeof(float)), nullptr, GL_DYNAMIC_DRAW);
    // Every shading level of the representative: its members share those programs (check_draw_levels).
    for (const GpuShading& sh : rep->shadings) g->inputs.push_back(vertex_input(*sh.program, layout, true, g->vbo, g->ebo));
    groups_.push_back(std::move(g));
  }
}

void GpuScene::update_groups(const FrameState& frame, RendererStats& stats) {
  const auto t0 = std::chrono::steady_clock::now();
  for (auto& g : groups_) {
    std::size_t lo = g->vertices.size(), hi = 0;
    bool rebuild = false;
    for (auto& m : g->members) {
      const auto node = static_cast<std::size_t>(m.draw->item->node);
      const glm::mat4& w = frame.world[node];
      const char vis = frame.visible[node] ? 1 : 0;
      const Primitive& p = *m.draw->prim;
      const std::size_t stride = static_cast<std::size_t>(merged_stride(p));
      std::span<float> dst(g->vertices.data() + std::size_t(m.first_vertex) * stride, std::size_t(p.vertex_count) * stride);
      const auto draw = static_cast<std::size_t>(m.draw->item - scene_.draws.data());
      const int lod = frame.draws[draw].lod;
      if (lod != m.lod) m.lod = lod, rebuild = true;
      const auto& shadings = m.draw->shadings;
      const bool flat = shadings[std::min(static_cast<std::size_t>(frame.draws[draw].shading), shadings.size() - 1)].flat_lists;
      if (flat != m.flat) m.flat = flat, rebuild = true;
      if (!m.uploaded || w != m.world) {
        transform_member(p, w, float(vis), dst);
        m.world = w;
        m.uploaded = true;
        ++stats.member_transforms;
        stats.vertices_transformed += p.vertex_count;
        const bool mir = glm::determinant(glm::mat3(w)) < 0.0f;
        if (mir != m.mirrored) m.mirrored = mir, rebuild = true;
      } else if (vis == m.visible) {
        continue;
      } else {
        set_member_alpha(p, float(vis), dst);
      }
      if (vis != m.visible) m.visible = vis, rebuild = true;
      lo = std::min(lo, std::size_t(m.first_vertex) * stride);
      hi = std::max(hi, std::size_t(m.first_vertex) * stride + dst.size());
    }
    if (lo < hi) {
      gl_.BindBuffer(GL_ARRAY_BUFFER, g->vbo);
      gl_.BufferSubData(GL_ARRAY_BUFFER, static_cast<GLintptr>(lo * sizeof(float)), static_cast<GLsizeiptr>((hi - lo) * sizeof(float)),
                        g->vertices.data() + lo);
    }
    if (rebuild) {
      // Index compaction: hidden members are left out, so they cost no vertex or pixel work.
      g->indices.clear();
      for (const auto& m : g->members) {
        if (!m.visible) continue;
        const Primitive& p = *m.draw->prim;
        const auto& list = m.lod == 0 ? (m.flat ? p.flat_indices : p.indices)
                                      : (m.flat ? p.lods[static_cast<std::size_t>(m.lod - 1)].flat_indices
                                                : p.lods[static_cast<std::size_t>(m.lod - 1)].indices);
        append_member_indices(std::span<const std::uint32_t>(list), m.first_vertex, m.mirrored, g->indices);
      }
      g->index_count = static_cast<GLsizei>(g->indices.size());
      gl_.BindVertexArray(0);
      gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, g->ebo);
      gl_.BufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(1, g->indices.size()) * sizeof(std::uint32_t)),
                     g->indices.empty() ? nullptr : g->indices.data(), GL_DYNAMIC_DRAW);
      ++stats.index_rebuilds;
    }
  }
  stats.concat_cpu_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace meter::engine
