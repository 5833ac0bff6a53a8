#include "meter/engine/renderer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "meter/engine/merged_draws.hpp"
#include "meter/platform/gl_api.hpp"

#ifndef METER_FONT_FILE
#define METER_FONT_FILE "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
#endif

namespace meter::engine {

using bridge::AttributeSemantic;
using bridge::UniformSemantic;
using Clock = std::chrono::steady_clock;

namespace {
double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}
}  // namespace

struct Renderer::GpuProgram {
  GLuint program = 0;
  const bridge::Program* info = nullptr;
  struct Uniform {
    GLint location = -1;
    UniformSemantic semantic{};
    int index = -1, array_size = 1;
  };
  std::vector<Uniform> uniforms;
  struct Sampler {
    GLint location = -1;
    bridge::TextureSlot slot{};
    int unit = 0;
  };
  std::vector<Sampler> samplers;
};

struct Renderer::GpuDraw {
  const DrawItem* item = nullptr;
  const Primitive* prim = nullptr;
  GpuProgram* program = nullptr;
  GLuint vao = 0;
  GLsizei index_count = 0;
  // Program attributes the primitive lacks: constant values set before the draw.
  std::vector<std::pair<GLuint, glm::vec4>> constant_attributes;
  float sort_depth = 0.0f;
  Renderer::GpuGroup* group = nullptr;  // set on a merged group's representative only
  // The program generated for this draw: blend and cull state, and (uber mode) the switches.
  const bridge::Program* shape = nullptr;
  // Can look different from one frame to the next (classify_draws); false: static-layer material.
  // A merged group's representative: true when any member can change.
  bool changeable = false;
};

// One merged group: world-space vertices of every member in one dynamic buffer, indices of the
// visible members only. Member ranges are rewritten only when that member's world matrix or
// visibility changed, so a static scene costs nothing per frame.
struct Renderer::GpuGroup {
  const MergedGroup* info = nullptr;
  GLuint vao = 0, vbo = 0, ebo = 0;
  std::vector<float> vertices;
  std::vector<std::uint32_t> indices;
  GLsizei index_count = 0;
  std::vector<std::pair<GLuint, glm::vec4>> constant_attributes;
  struct Member {
    const GpuDraw* draw = nullptr;
    std::uint32_t first_vertex = 0;
    glm::mat4 world{0.0f};
    bool uploaded = false, mirrored = false;
    char visible = -1;
  };
  std::vector<Member> members;
};

Renderer::Renderer(platform::GpuBackend& backend, const Scene& scene, const RendererOptions& options)
    : backend_(backend), gl_(backend.gl()), scene_(scene), options_(options) {
  width_ = options.width > 0 ? options.width : scene.config.size[0];
  height_ = options.height > 0 ? options.height : scene.config.size[1];
  platform::RenderTargetOptions rt;
  rt.width = width_;
  rt.height = height_;
  rt.samples = std::max(1, options.msaa);
  rt.depth = platform::DepthFormat::Depth24;
  target_ = std::make_unique<platform::RenderTarget>(backend, rt);
  unresolved_ = {platform::PixelRegion{0, 0, width_, height_}};
  pose_ = Pose::rest(scene);
  anim_time_.assign(scene.animations.size(), std::nan(""));
  visible_.assign(scene.nodes.size(), 1);
  build();
  // Animations nobody drives sit at config.time from the start.
  BindingOutputs initial;
  initial.animation_time.assign(scene.animations.size(), scene.config.time);
  initial.node_visible.assign(scene.nodes.size(), -1);
  initial.emissive.assign(scene.materials.size(), std::nullopt);
  initial.base_color.assign(scene.materials.size(), std::nullopt);
  apply(initial);
}

Renderer::~Renderer() {
  backend_.make_current();
  for (auto& d : draws_) gl_.DeleteVertexArrays(1, &d->vao);
  for (auto& g : groups_) {
    gl_.DeleteVertexArrays(1, &g->vao);
    gl_.DeleteBuffers(1, &g->vbo);
    gl_.DeleteBuffers(1, &g->ebo);
  }
  if (!buffers_.empty()) gl_.DeleteBuffers(static_cast<GLsizei>(buffers_.size()), buffers_.data());
  if (!textures_.empty()) gl_.DeleteTextures(static_cast<GLsizei>(textures_.size()), textures_.data());
  if (white_texture_) gl_.DeleteTextures(1, &white_texture_);
  for (auto& p : programs_) gl_.DeleteProgram(p->program);
}

std::string Renderer::backend_info() const { return backend_.renderer_info(); }

namespace {
bool is_light_semantic(UniformSemantic s) {
  return s == UniformSemantic::LightColor || s == UniformSemantic::LightIntensity || s == UniformSemantic::LightPosition ||
         s == UniformSemantic::LightDirection || s == UniformSemantic::LightRange ||
         s == UniformSemantic::LightInnerConeCos || s == UniformSemantic::LightOuterConeCos;
}

// Runtime switches of shadergen::generate_uber() for a draw generated with `f` (the bit layout is
// uber.cpp's). Slot 0: vertex stage, slot 1: fragment stage.
glm::ivec4 uber_switches(const bridge::MaterialFeatures& f, int slot) {
  using bridge::ShadingModel;
  int textures = 0;
  const bool tex[5] = {f.base_color_texture, f.metallic_roughness_texture, f.normal_texture, f.emissive_texture,
                       f.occlusion_texture};
  for (int k = 0; k < 5; ++k) textures |= tex[k] ? 1 << k : 0;
  if (slot == 0) return {0, 0, (f.vertex_colors ? 1 : 0) | (f.skin_joints > 0 ? 2 : 0), 0};
  const int model = f.shading == ShadingModel::Unlit ? 0 : f.shading == ShadingModel::PbrMetallicRoughness ? 2 : 1;
  const int bits = (f.double_sided ? 4 : 0) | (f.has_tangents ? 8 : 0) | (f.texture_transform ? 16 : 0);
  return {model, textures, bits, static_cast<int>(f.alpha) | static_cast<int>(f.texcoord1_slots << 4)};
}
}  // namespace

void Renderer::build() {
  // Programs: the package's generated ones, or (benchmark baseline) the uber-shader alone.
  auto add_program = [&](const bridge::Program& p, const std::string& label) {
    auto gp = std::make_unique<GpuProgram>();
    gp->info = &p;
    gp->program = platform::compile_program(gl_, p.vertex_source, p.fragment_source, label);
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
      GpuProgram::Sampler gs{gl_.GetUniformLocation(gp->program, s.name.c_str()), s.slot, s.unit};
      if (gs.location >= 0) gp->samplers.push_back(gs);
    }
    programs_.push_back(std::move(gp));
  };
  if (options_.uber_shader) {
    if (!options_.uber_shader->uber) throw SceneError("RendererOptions::uber_shader is not an uber-shader program");
    add_program(*options_.uber_shader, scene_.source_name + " uber-shader");
    options_.concatenate = false;  // the uber-shader has no vertex-alpha input
  } else {
    for (std::size_t i = 0; i < scene_.programs.size(); ++i)
      add_program(scene_.programs[i].program, scene_.source_name + " program " + std::to_string(i));
  }
  // Textures.
  for (const auto& t : scene_.textures) {
    GLuint tex = 0;
    gl_.GenTextures(1, &tex);
    gl_.BindTexture(GL_TEXTURE_2D, tex);
    gl_.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl_.TexImage2D(GL_TEXTURE_2D, 0, t.srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8, t.width, t.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, t.rgba.data());
    const bool mip = t.min_filter == GL_NEAREST_MIPMAP_NEAREST || t.min_filter == GL_LINEAR_MIPMAP_NEAREST ||
                     t.min_filter == GL_NEAREST_MIPMAP_LINEAR || t.min_filter == GL_LINEAR_MIPMAP_LINEAR;
    if (mip) gl_.GenerateMipmap(GL_TEXTURE_2D);
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
  {
    const std::uint8_t white[4] = {255, 255, 255, 255};
    gl_.GenTextures(1, &white_texture_);
    gl_.BindTexture(GL_TEXTURE_2D, white_texture_);
    gl_.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, white);
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
  // Vertex/index buffers, one pair per primitive, shared by every draw of it.
  std::map<std::pair<int, int>, std::pair<GLuint, GLuint>> vbos;
  for (const auto& d : scene_.draws) {
    const Primitive& prim = scene_.meshes[static_cast<std::size_t>(d.mesh)].primitives[static_cast<std::size_t>(d.primitive)];
    auto key = std::make_pair(d.mesh, d.primitive);
    if (!vbos.count(key)) {
      GLuint b[2];
      gl_.GenBuffers(2, b);
      gl_.BindBuffer(GL_ARRAY_BUFFER, b[0]);
      gl_.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(prim.vertices.size() * sizeof(float)), prim.vertices.data(), GL_STATIC_DRAW);
      gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, b[1]);
      gl_.BufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(prim.indices.size() * sizeof(std::uint32_t)), prim.indices.data(), GL_STATIC_DRAW);
      buffers_.insert(buffers_.end(), {b[0], b[1]});
      vbos[key] = {b[0], b[1]};
    }
    auto gd = std::make_unique<GpuDraw>();
    gd->item = &d;
    gd->prim = &prim;
    gd->shape = &scene_.programs[static_cast<std::size_t>(d.program)].program;
    gd->program = programs_[options_.uber_shader ? 0 : static_cast<std::size_t>(d.program)].get();
    gd->index_count = static_cast<GLsizei>(prim.indices.size());
    gl_.GenVertexArrays(1, &gd->vao);
    gl_.BindVertexArray(gd->vao);
    gl_.BindBuffer(GL_ARRAY_BUFFER, vbos[key].first);
    gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, vbos[key].second);
    for (const auto& a : gd->program->info->attributes) {
      auto it = std::find_if(prim.layout.begin(), prim.layout.end(), [&](const VertexAttribute& v) {
        return v.semantic == a.semantic && (v.index == a.index || (v.index < 0 && a.index < 0));
      });
      const auto loc = static_cast<GLuint>(a.location);
      if (it == prim.layout.end()) {
        // Missing data gets the neutral value: white vertex colour, full vertex alpha, zero otherwise.
        glm::vec4 c(0.0f, 0.0f, 0.0f, 1.0f);
        if (a.semantic == AttributeSemantic::Color0 || a.semantic == AttributeSemantic::VertexAlpha) c = glm::vec4(1.0f);
        if (a.semantic == AttributeSemantic::Weights0) c = glm::vec4(1.0f, 0.0f, 0.0f, 0.0f);
        gd->constant_attributes.emplace_back(loc, c);
        continue;
      }
      gl_.EnableVertexAttribArray(loc);
      gl_.VertexAttribPointer(loc, it->components, GL_FLOAT, GL_FALSE, prim.stride * static_cast<GLsizei>(sizeof(float)),
                              reinterpret_cast<const void*>(static_cast<std::uintptr_t>(it->offset) * sizeof(float)));
    }
    gl_.BindVertexArray(0);
    draws_.push_back(std::move(gd));
  }
  build_groups();
  platform::check_gl(gl_, scene_.source_name + ": uploading the scene");
  // Camera: the configured one, else the first camera node reachable from the roots.
  for (std::size_t i = 0; i < scene_.nodes.size(); ++i) {
    const Node& n = scene_.nodes[i];
    if (n.camera < 0) continue;
    if (scene_.config.camera.empty() || n.name == scene_.config.camera ||
        scene_.cameras[static_cast<std::size_t>(n.camera)].name == scene_.config.camera) {
      camera_node_ = static_cast<int>(i);
      break;
    }
  }
  order_lights();
  classify_draws();
}

void Renderer::order_lights() {
  // Shadergen's order: preorder from the roots, then stable by type. It depends on the scene's
  // structure only, so it is fixed for the renderer's life.
  light_nodes_.clear();
  std::vector<int> stack(scene_.roots.rbegin(), scene_.roots.rend());
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    const Node& nd = scene_.nodes[static_cast<std::size_t>(n)];
    if (nd.light >= 0) light_nodes_.push_back(n);
    stack.insert(stack.end(), nd.children.rbegin(), nd.children.rend());
  }
  auto type = [&](int node) {
    return static_cast<int>(scene_.lights[static_cast<std::size_t>(scene_.nodes[static_cast<std::size_t>(node)].light)].type);
  };
  std::stable_sort(light_nodes_.begin(), light_nodes_.end(), [&](int a, int b) { return type(a) < type(b); });
  for (std::size_t k = 0; k < light_nodes_.size(); ++k)
    if (light_count_[type(light_nodes_[k])]++ == 0) light_first_[type(light_nodes_[k])] = static_cast<int>(k);
}

void Renderer::build_groups() {
  draw_group_.assign(draws_.size(), -1);
  if (!options_.concatenate) return;
  for (const auto& mg : scene_.groups) {
    auto g = std::make_unique<GpuGroup>();
    g->info = &mg;
    std::uint32_t vertices = 0;
    for (int d : mg.draws) {
      GpuGroup::Member m;
      m.draw = draws_[static_cast<std::size_t>(d)].get();
      m.first_vertex = vertices;
      vertices += m.draw->prim->vertex_count;
      g->members.push_back(m);
      draw_group_[static_cast<std::size_t>(d)] = static_cast<int>(groups_.size());
    }
    GpuDraw* rep = draws_[static_cast<std::size_t>(mg.draws.front())].get();
    rep->group = g.get();
    const Primitive& layout = *rep->prim;
    const int stride = merged_stride(layout);
    g->vertices.assign(std::size_t(vertices) * std::size_t(stride), 0.0f);
    GLuint b[2];
    gl_.GenBuffers(2, b);
    g->vbo = b[0], g->ebo = b[1];
    gl_.GenVertexArrays(1, &g->vao);
    gl_.BindVertexArray(g->vao);
    gl_.BindBuffer(GL_ARRAY_BUFFER, g->vbo);
    // DYNAMIC: rewritten (in member ranges) whenever a member moves.
    gl_.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(g->vertices.size() * sizeof(float)), nullptr, GL_DYNAMIC_DRAW);
    gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, g->ebo);
    for (const auto& a : rep->program->info->attributes) {
      const auto loc = static_cast<GLuint>(a.location);
      int components = 0, offset = 0;
      if (a.semantic == AttributeSemantic::VertexAlpha) {
        components = 1, offset = layout.stride;
      } else {
        auto it = std::find_if(layout.layout.begin(), layout.layout.end(), [&](const VertexAttribute& v) {
          return v.semantic == a.semantic && (v.index == a.index || (v.index < 0 && a.index < 0));
        });
        if (it == layout.layout.end()) {
          glm::vec4 c(0.0f, 0.0f, 0.0f, 1.0f);
          if (a.semantic == AttributeSemantic::Color0) c = glm::vec4(1.0f);
          g->constant_attributes.emplace_back(loc, c);
          continue;
        }
        components = it->components, offset = it->offset;
      }
      gl_.EnableVertexAttribArray(loc);
      gl_.VertexAttribPointer(loc, components, GL_FLOAT, GL_FALSE, stride * static_cast<GLsizei>(sizeof(float)),
                              reinterpret_cast<const void*>(static_cast<std::uintptr_t>(offset) * sizeof(float)));
    }
    gl_.BindVertexArray(0);
    groups_.push_back(std::move(g));
  }
}

void Renderer::classify_draws() {
  // What the scene's animations and bindings can reach. An animation nobody drives stays at
  // config.time, but it is counted as moving anyway: this decides what may be cached, so it errs
  // towards drawing more, never towards a stale layer (render() also checks the layer each frame).
  std::vector<char> node_moves(scene_.nodes.size(), 0), material_changes(scene_.materials.size(), 0);
  auto mark = [](std::vector<char>& v, int i) {
    if (i >= 0 && static_cast<std::size_t>(i) < v.size()) v[static_cast<std::size_t>(i)] = 1;
  };
  for (const auto& a : scene_.animations)
    for (const auto& ch : a.channels) mark(node_moves, ch.node);
  for (const auto& b : scene_.config.bindings) {
    if (b.kind == BindingKind::Visibility || b.kind == BindingKind::Morph) mark(node_moves, scene_.find_node(b.node));
    if (b.kind == BindingKind::Emissive || b.kind == BindingKind::Color) mark(material_changes, scene_.find_material(b.material));
  }
  // Transforms and visibility are inherited: below a moving node everything moves.
  std::vector<int> stack(scene_.roots.begin(), scene_.roots.end());
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    for (int c : scene_.nodes[static_cast<std::size_t>(n)].children) {
      if (node_moves[static_cast<std::size_t>(n)]) node_moves[static_cast<std::size_t>(c)] = 1;
      stack.push_back(c);
    }
  }
  for (auto& d : draws_) {
    const auto node = static_cast<std::size_t>(d->item->node);
    d->changeable = node_moves[node] || material_changes[static_cast<std::size_t>(d->prim->material)] ||
                    scene_.nodes[node].skin >= 0 || d->prim->morph_targets > 0;
  }
  for (auto& g : groups_) {
    GpuDraw* rep = draws_[static_cast<std::size_t>(g->info->draws.front())].get();
    for (const auto& m : g->members) rep->changeable = rep->changeable || m.draw->changeable;
  }
  // A layer pays off only if it has content and outlives a frame: not when the view can move (an
  // animated camera, or no camera, where the view frames the bounds of moving draws too) or a
  // light can (every pixel changes), which would redraw it every frame.
  bool any_static_opaque = false;
  for (std::size_t i = 0; i < draws_.size(); ++i) {
    const GpuDraw& d = *draws_[i];
    const bool drawn_alone_or_for_group = draw_group_[i] < 0 || d.group;
    if (drawn_alone_or_for_group && !d.changeable && !d.shape->blend) any_static_opaque = true;
  }
  bool view_fixed = camera_node_ >= 0 && !node_moves[static_cast<std::size_t>(camera_node_)];
  for (std::size_t n = 0; n < scene_.nodes.size(); ++n)
    if (scene_.nodes[n].light >= 0 && node_moves[n]) view_fixed = false;
  layer_pays_ = any_static_opaque && view_fixed;
}

void Renderer::update_groups() {
  const auto t0 = Clock::now();
  for (auto& g : groups_) {
    std::size_t lo = g->vertices.size(), hi = 0;
    bool rebuild = false;
    for (auto& m : g->members) {
      const auto node = static_cast<std::size_t>(m.draw->item->node);
      const glm::mat4& w = world_[node];
      const char vis = visible_[node] ? 1 : 0;
      const Primitive& p = *m.draw->prim;
      const std::size_t stride = static_cast<std::size_t>(merged_stride(p));
      std::span<float> dst(g->vertices.data() + std::size_t(m.first_vertex) * stride, std::size_t(p.vertex_count) * stride);
      if (!m.uploaded || w != m.world) {
        transform_member(p, w, float(vis), dst);
        m.world = w;
        m.uploaded = true;
        ++stats_.member_transforms;
        stats_.vertices_transformed += p.vertex_count;
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
        if (m.visible) append_member_indices(*m.draw->prim, m.first_vertex, m.mirrored, g->indices);
      }
      g->index_count = static_cast<GLsizei>(g->indices.size());
      gl_.BindVertexArray(0);
      gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, g->ebo);
      gl_.BufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(1, g->indices.size()) * sizeof(std::uint32_t)),
                     g->indices.empty() ? nullptr : g->indices.data(), GL_DYNAMIC_DRAW);
      ++stats_.index_rebuilds;
    }
  }
  stats_.concat_cpu_ms += ms_since(t0);
}

void Renderer::apply(const BindingOutputs& o) {
  // Animations: re-sample only those whose time changed.
  std::vector<int> touched;
  for (std::size_t a = 0; a < scene_.animations.size() && a < o.animation_time.size(); ++a) {
    if (anim_time_[a] == o.animation_time[a]) continue;
    anim_time_[a] = o.animation_time[a];
    apply_animation(scene_, static_cast<int>(a), anim_time_[a], pose_, &touched);
    ++stats_.animation_samples;
  }
  if (!touched.empty()) world_dirty_ = true, dirty_ = true;
  if (!have_outputs_ || !(o.node_visible == outputs_.node_visible && o.emissive == outputs_.emissive &&
                          o.base_color == outputs_.base_color && o.morph == outputs_.morph && o.texts == outputs_.texts &&
                          o.link_lost == outputs_.link_lost)) {
    dirty_ = true;
    if (!have_outputs_ || o.node_visible != outputs_.node_visible) {
      // Effective visibility: a hidden node hides its subtree.
      visible_.assign(scene_.nodes.size(), 1);
      std::vector<std::pair<int, bool>> stack;
      for (int r : scene_.roots) stack.emplace_back(r, true);
      while (!stack.empty()) {
        auto [n, parent_visible] = stack.back();
        stack.pop_back();
        const auto i = static_cast<std::size_t>(n);
        bool v = parent_visible && (i >= o.node_visible.size() || o.node_visible[i] != 0);
        visible_[i] = v;
        for (int c : scene_.nodes[i].children) stack.emplace_back(c, v);
      }
    }
    outputs_ = o;
    have_outputs_ = true;
  }
}

void Renderer::update_world() {
  if (!world_dirty_) return;
  world_matrices(scene_, pose_, world_);
  world_dirty_ = false;
  ++stats_.world_updates;
}

glm::mat4 Renderer::view_projection(glm::vec3* eye) const {
  const float aspect = float(width_) / float(height_);
  if (camera_node_ >= 0) {
    const Camera& c = scene_.cameras[static_cast<std::size_t>(scene_.nodes[static_cast<std::size_t>(camera_node_)].camera)];
    glm::mat4 w = world_[static_cast<std::size_t>(camera_node_)];
    // Cameras ignore scale (glTF): orthonormalise the axes.
    for (int k = 0; k < 3; ++k) w[k] = glm::vec4(glm::normalize(glm::vec3(w[k])), 0.0f);
    if (eye) *eye = glm::vec3(w[3]);
    glm::mat4 view = glm::inverse(w);
    glm::mat4 proj;
    if (c.perspective) {
      proj = c.zfar > 0 ? glm::perspective(c.yfov, aspect, c.znear, c.zfar) : glm::infinitePerspective(c.yfov, aspect, c.znear);
    } else {
      proj = glm::ortho(-c.xmag, c.xmag, -c.ymag, c.ymag, c.znear, c.zfar);
    }
    return proj * view;
  }
  // No camera in the scene: frame the bounds of everything drawn, looking down -Z.
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const auto& d : draws_) {
    const glm::mat4& w = world_[static_cast<std::size_t>(d->item->node)];
    for (int k = 0; k < 8; ++k) {
      glm::vec3 p((k & 1) ? d->prim->bounds_max.x : d->prim->bounds_min.x, (k & 2) ? d->prim->bounds_max.y : d->prim->bounds_min.y,
                  (k & 4) ? d->prim->bounds_max.z : d->prim->bounds_min.z);
      glm::vec3 q(w * glm::vec4(p, 1.0f));
      lo = glm::min(lo, q), hi = glm::max(hi, q);
    }
  }
  if (draws_.empty()) lo = glm::vec3(-1.0f), hi = glm::vec3(1.0f);
  const glm::vec3 centre = (lo + hi) * 0.5f;
  const float radius = std::max(1e-3f, glm::length(hi - lo) * 0.5f);
  const float yfov = 0.8f;
  const float dist = radius / std::sin(yfov * 0.5f) * 1.05f;
  const glm::vec3 e = centre + glm::vec3(0.0f, 0.0f, dist);
  if (eye) *eye = e;
  return glm::perspective(yfov, aspect, std::max(1e-3f, dist - radius * 2.0f), dist + radius * 2.0f) *
         glm::lookAt(e, centre, glm::vec3(0.0f, 1.0f, 0.0f));
}

glm::vec2 Renderer::project(int node) const {
  if (node < 0 || static_cast<std::size_t>(node) >= world_.size()) return glm::vec2(0.0f);
  glm::vec4 clip = view_projection(nullptr) * glm::vec4(glm::vec3(world_[static_cast<std::size_t>(node)][3]), 1.0f);
  if (std::abs(clip.w) < 1e-9f) return glm::vec2(-1e6f);
  glm::vec2 ndc(clip.x / clip.w, clip.y / clip.w);
  return glm::vec2((ndc.x * 0.5f + 0.5f) * float(width_), (1.0f - (ndc.y * 0.5f + 0.5f)) * float(height_));
}

void Renderer::draw_scene(platform::RenderTarget& target, const platform::PixelRegion* scissor, DrawSet set) {
  const auto& gl = gl_;
  target.bind();
  // The scissor clips the clear and every draw below (and the text after it) to the region.
  if (scissor) {
    gl.Enable(GL_SCISSOR_TEST);
    gl.Scissor(scissor->x, scissor->y, scissor->width, scissor->height);
  } else {
    gl.Disable(GL_SCISSOR_TEST);
  }
  const auto& cc = scene_.config.clear_color;
  gl.ClearColor(float(cc[0]), float(cc[1]), float(cc[2]), float(cc[3]));
  gl.ClearDepthf(1.0f);
  gl.DepthMask(GL_TRUE);
  // Over the static layer the region already holds its copy (colour and depth).
  if (set != DrawSet::OverStatic) gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  gl.Enable(GL_DEPTH_TEST);
  gl.DepthFunc(GL_LEQUAL);
  glm::vec3 eye(0.0f);
  const glm::mat4 vp = view_projection(&eye);

  const std::vector<int>& lights = light_nodes_;

  // Sort: opaque/mask front-to-back (early depth reject), blended back-to-front (correct over).
  update_groups();
  std::vector<GpuDraw*> opaque, blended;
  for (std::size_t i = 0; i < draws_.size(); ++i) {
    auto& d = draws_[i];
    if (draw_group_[i] >= 0) {
      // A merged group is drawn once, at its representative's place, if any member is visible
      // (the representative itself may be hidden).
      if (!d->group || d->group->index_count == 0) continue;
    } else if (!visible_[static_cast<std::size_t>(d->item->node)]) {
      continue;
    }
    const bool in_layer = !d->shape->blend && !d->changeable;
    if ((set == DrawSet::StaticOpaque && !in_layer) || (set == DrawSet::OverStatic && in_layer)) continue;
    // A draw whose screen box misses the scissor cannot change a pixel of this pass; on llvmpipe
    // skipping it saves its vertex work and triangle setup, which the scissor alone does not.
    if (scissor && outside(*d, *scissor, vp)) continue;
    const glm::vec3 c = (d->prim->bounds_min + d->prim->bounds_max) * 0.5f;
    glm::vec4 clip = vp * world_[static_cast<std::size_t>(d->item->node)] * glm::vec4(c, 1.0f);
    d->sort_depth = clip.w;
    (d->shape->blend ? blended : opaque).push_back(d.get());
  }
  std::stable_sort(opaque.begin(), opaque.end(), [](auto* a, auto* b) { return a->sort_depth < b->sort_depth; });
  // Static before changeable (the layer's order); each part stays front-to-back.
  std::stable_partition(opaque.begin(), opaque.end(), [](auto* d) { return !d->changeable; });
  std::stable_sort(blended.begin(), blended.end(), [](auto* a, auto* b) { return a->sort_depth > b->sort_depth; });

  std::vector<float> scratch;
  GpuProgram* current = nullptr;
  auto draw_one = [&](GpuDraw* d) {
    GpuProgram* gp = d->program;
    const auto node_index = static_cast<std::size_t>(d->item->node);
    const Node& node = scene_.nodes[node_index];
    const Material& mat = scene_.materials[static_cast<std::size_t>(d->prim->material)];
    static const glm::mat4 kIdentity(1.0f);
    // Merged vertices are already in world space.
    const glm::mat4& model = d->group ? kIdentity : world_[node_index];
    if (gp != current) {
      gl.UseProgram(gp->program);
      current = gp;
    }
    const bridge::Program& shape = *d->shape;
    if (shape.blend) {
      gl.Enable(GL_BLEND);
      gl.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
      gl.DepthMask(GL_FALSE);
    } else {
      gl.Disable(GL_BLEND);
      gl.DepthMask(GL_TRUE);
    }
    if (shape.cull_back_faces) {
      gl.Enable(GL_CULL_FACE);
      gl.CullFace(GL_BACK);
    } else {
      gl.Disable(GL_CULL_FACE);
    }
    // A mirroring transform flips the winding.
    gl.FrontFace(glm::determinant(glm::mat3(model)) < 0 ? GL_CW : GL_CCW);
    const auto mi = static_cast<std::size_t>(d->prim->material);
    const glm::vec4 base = outputs_.base_color.size() > mi && outputs_.base_color[mi] ? *outputs_.base_color[mi] : mat.base_color;
    const glm::vec3 emissive = outputs_.emissive.size() > mi && outputs_.emissive[mi] ? *outputs_.emissive[mi] : mat.emissive;
    for (const auto& u : gp->uniforms) {
      const GLint l = u.location;
      switch (u.semantic) {
        case UniformSemantic::ModelMatrix: gl.UniformMatrix4fv(l, 1, GL_FALSE, glm::value_ptr(model)); break;
        case UniformSemantic::ViewProjection: gl.UniformMatrix4fv(l, 1, GL_FALSE, glm::value_ptr(vp)); break;
        case UniformSemantic::NormalMatrix: {
          const glm::mat3 n = normal_matrix(model);  // finite even for a zero scale
          gl.UniformMatrix3fv(l, 1, GL_FALSE, glm::value_ptr(n));
          break;
        }
        case UniformSemantic::CameraPosition: gl.Uniform3f(l, eye.x, eye.y, eye.z); break;
        case UniformSemantic::BaseColorFactor: gl.Uniform4f(l, base.r, base.g, base.b, base.a); break;
        case UniformSemantic::EmissiveFactor: gl.Uniform3f(l, emissive.r, emissive.g, emissive.b); break;
        case UniformSemantic::MetallicFactor: gl.Uniform1f(l, mat.metallic); break;
        case UniformSemantic::RoughnessFactor: gl.Uniform1f(l, mat.roughness); break;
        case UniformSemantic::NormalScale: gl.Uniform1f(l, mat.normal_scale); break;
        case UniformSemantic::OcclusionStrength: gl.Uniform1f(l, mat.occlusion_strength); break;
        case UniformSemantic::AlphaCutoff: gl.Uniform1f(l, mat.alpha_cutoff); break;
        case UniformSemantic::SpecularColor: gl.Uniform3f(l, mat.specular_color.r, mat.specular_color.g, mat.specular_color.b); break;
        case UniformSemantic::Shininess: gl.Uniform1f(l, mat.shininess); break;
        case UniformSemantic::AmbientLight: gl.Uniform3f(l, scene_.ambient.r, scene_.ambient.g, scene_.ambient.b); break;
        case UniformSemantic::Exposure: gl.Uniform1f(l, static_cast<float>(std::exp2(scene_.config.exposure))); break;
        case UniformSemantic::EnvironmentIntensity: gl.Uniform1f(l, scene_.environment.strength); break;
        case UniformSemantic::EnvironmentIrradiance:
          if (u.index >= 0 && u.index < 6) {
            const glm::vec3& e = scene_.environment.irradiance[static_cast<std::size_t>(u.index)];
            gl.Uniform3f(l, e.r, e.g, e.b);
          }
          break;
        case UniformSemantic::LightColor:
        case UniformSemantic::LightIntensity:
        case UniformSemantic::LightPosition:
        case UniformSemantic::LightDirection:
        case UniformSemantic::LightRange:
        case UniformSemantic::LightInnerConeCos:
        case UniformSemantic::LightOuterConeCos: {
          int index = u.index;
          if (gp->info->uber) {
            // Uber arrays: index = 2 * type + k (k-th light of that type); generated programs
            // index the type-sorted list directly.
            const int type = index / 2, k = index % 2;
            index = k < light_count_[type] ? light_first_[type] + k : -1;
          }
          if (index < 0 || static_cast<std::size_t>(index) >= lights.size()) break;
          const int ln = lights[static_cast<std::size_t>(index)];
          const Light& li = scene_.lights[static_cast<std::size_t>(scene_.nodes[static_cast<std::size_t>(ln)].light)];
          const glm::mat4& lw = world_[static_cast<std::size_t>(ln)];
          if (u.semantic == UniformSemantic::LightColor) gl.Uniform3f(l, li.color.r, li.color.g, li.color.b);
          if (u.semantic == UniformSemantic::LightIntensity) gl.Uniform1f(l, li.intensity);
          if (u.semantic == UniformSemantic::LightRange) gl.Uniform1f(l, li.range);
          if (u.semantic == UniformSemantic::LightInnerConeCos) gl.Uniform1f(l, std::cos(li.inner_cone));
          if (u.semantic == UniformSemantic::LightOuterConeCos) gl.Uniform1f(l, std::cos(li.outer_cone));
          if (u.semantic == UniformSemantic::LightPosition) gl.Uniform3f(l, lw[3].x, lw[3].y, lw[3].z);
          if (u.semantic == UniformSemantic::LightDirection) {
            glm::vec3 dir = glm::normalize(glm::vec3(lw * glm::vec4(0.0f, 0.0f, -1.0f, 0.0f)));
            gl.Uniform3f(l, dir.x, dir.y, dir.z);
          }
          break;
        }
        case UniformSemantic::JointMatrices: {
          if (node.skin < 0) break;
          const Skin& skin = scene_.skins[static_cast<std::size_t>(node.skin)];
          const glm::mat4 inv_model = glm::inverse(model);
          scratch.assign(static_cast<std::size_t>(u.array_size) * 16, 0.0f);
          for (std::size_t j = 0; j < skin.joints.size() && j < static_cast<std::size_t>(u.array_size); ++j) {
            glm::mat4 jm = inv_model * world_[static_cast<std::size_t>(skin.joints[j])] * skin.inverse_bind[j];
            std::copy(glm::value_ptr(jm), glm::value_ptr(jm) + 16, scratch.begin() + static_cast<std::ptrdiff_t>(j * 16));
          }
          gl.UniformMatrix4fv(l, u.array_size, GL_FALSE, scratch.data());
          break;
        }
        case UniformSemantic::MorphWeights: {
          scratch.assign(static_cast<std::size_t>(u.array_size), 0.0f);
          const auto& w = pose_.weights[node_index];
          for (std::size_t k = 0; k < w.size() && k < scratch.size(); ++k) scratch[k] = w[k];
          for (const auto& m : outputs_.morph) {
            if (m.node == d->item->node && m.target >= 0 && static_cast<std::size_t>(m.target) < scratch.size()) scratch[static_cast<std::size_t>(m.target)] = m.weight;
          }
          gl.Uniform1fv(l, u.array_size, scratch.data());
          break;
        }
        case UniformSemantic::TextureTransform:
          if (u.index >= 0 && u.index < 6) gl.UniformMatrix3fv(l, 1, GL_FALSE, glm::value_ptr(mat.uv_transform[static_cast<std::size_t>(u.index)]));
          break;
        case UniformSemantic::UberSwitches: {  // uber baseline only; never in a package
          const glm::ivec4 sw = uber_switches(shape.features, u.index);
          gl.Uniform4i(l, sw.x, sw.y, sw.z, sw.w);
          break;
        }
        case UniformSemantic::UberLightCounts: {
          const auto& c = shape.features.lights;
          gl.Uniform3i(l, std::min(c.directional, 2), std::min(c.point, 2), std::min(c.spot, 2));
          break;
        }
      }
    }
    for (const auto& s : gp->samplers) {
      const int tex = s.slot == bridge::TextureSlot::Environment ? scene_.environment.texture
                                                                     : mat.texture[static_cast<std::size_t>(s.slot)];
      gl.ActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + s.unit));
      gl.BindTexture(GL_TEXTURE_2D, tex >= 0 ? textures_[static_cast<std::size_t>(tex)] : white_texture_);
      gl.Uniform1i(s.location, s.unit);
    }
    gl.BindVertexArray(d->group ? d->group->vao : d->vao);
    for (const auto& [loc, v] : d->group ? d->group->constant_attributes : d->constant_attributes) gl.VertexAttrib4f(loc, v.x, v.y, v.z, v.w);
    gl.DrawElements(GL_TRIANGLES, d->group ? d->group->index_count : d->index_count, GL_UNSIGNED_INT, nullptr);
    ++stats_.draw_calls;
  };
  for (auto* d : opaque) draw_one(d);
  for (auto* d : blended) draw_one(d);
  gl.BindVertexArray(0);
  gl.DepthMask(GL_TRUE);
  gl.Disable(GL_BLEND);
  gl.UseProgram(0);
}

namespace {
platform::Align to_platform(TextAlign a) {
  return a == TextAlign::Left ? platform::Align::Left : a == TextAlign::Center ? platform::Align::Center : platform::Align::Right;
}
bool drawable(const TextItem& t, const std::vector<char>& visible) {
  return t.node >= 0 && static_cast<std::size_t>(t.node) < visible.size() && visible[static_cast<std::size_t>(t.node)] &&
         !t.text.empty();
}
}  // namespace

platform::TextRenderer& Renderer::text_renderer(int size_px) {
  // Text sizes are designed at the scene config's size; a target of another size (--size, the
  // half-size frames of the vcan tests) scales them with its height, so the layout keeps its
  // proportions instead of readouts running into each other.
  const int design_height = scene_.config.size[1] > 0 ? scene_.config.size[1] : height_;
  const double scaled = double(size_px) * double(height_) / double(design_height);
  const int size = std::clamp(static_cast<int>(std::lround(scaled)), 4, 256);
  auto it = text_.find(size);
  if (it == text_.end()) {
    const std::string font = options_.font_file.empty() ? std::string(METER_FONT_FILE) : options_.font_file;
    it = text_.emplace(size, std::make_unique<platform::TextRenderer>(backend_, font, size)).first;
  }
  return *it->second;
}

void Renderer::draw_text() {
  for (const auto& t : outputs_.texts) {
    if (!drawable(t, visible_)) continue;
    platform::TextRenderer& tr = text_renderer(t.size_px);
    const glm::vec2 p = project(t.node);
    const int x = static_cast<int>(std::lround(p.x)), y = static_cast<int>(std::lround(p.y));
    const platform::Color color{t.color.r, t.color.g, t.color.b, t.color.a};
    try {
      tr.draw(*target_, t.text, x, y, to_platform(t.align), color);
    } catch (const platform::TextError&) {
      // Invalid UTF-8 from a signal: draw the placeholder rather than nothing.
      tr.draw(*target_, "?", x, y, to_platform(t.align), color);
    }
  }
}

// ---- Partial redraw: which pixels can differ from the last drawn frame -------------------------

namespace {
using platform::PixelRegion;

long long area(const PixelRegion& r) { return r.empty() ? 0 : static_cast<long long>(r.width) * r.height; }
PixelRegion unite(const PixelRegion& a, const PixelRegion& b) {
  const int x0 = std::min(a.x, b.x), y0 = std::min(a.y, b.y);
  const int x1 = std::max(a.x + a.width, b.x + b.width), y1 = std::max(a.y + a.height, b.y + b.height);
  return {x0, y0, x1 - x0, y1 - y0};
}
bool overlap(const PixelRegion& a, const PixelRegion& b) {
  return a.x < b.x + b.width && b.x < a.x + a.width && a.y < b.y + b.height && b.y < a.y + a.height;
}

// Clips to the target, then merges until the regions are disjoint (text is alpha-blended: a pixel
// in two regions would get it twice) and at most kMaxRegions remain (each region is one more pass
// over every draw call), merging first the pair whose union adds the least area.
void normalise(std::vector<PixelRegion>& regions, int width, int height) {
  constexpr std::size_t kMaxRegions = 4;
  for (auto& r : regions) r = platform::clip(r, width, height);
  std::erase_if(regions, [](const PixelRegion& r) { return r.empty(); });
  for (;;) {
    bool merged = false;
    for (std::size_t i = 0; i < regions.size() && !merged; ++i)
      for (std::size_t j = i + 1; j < regions.size() && !merged; ++j)
        if (overlap(regions[i], regions[j])) {
          regions[i] = unite(regions[i], regions[j]);
          regions.erase(regions.begin() + static_cast<std::ptrdiff_t>(j));
          merged = true;
        }
    if (merged) continue;
    if (regions.size() <= kMaxRegions) return;
    std::size_t bi = 0, bj = 1;
    long long best = std::numeric_limits<long long>::max();
    for (std::size_t i = 0; i < regions.size(); ++i)
      for (std::size_t j = i + 1; j < regions.size(); ++j) {
        const long long cost = area(unite(regions[i], regions[j])) - area(regions[i]) - area(regions[j]);
        if (cost < best) best = cost, bi = i, bj = j;
      }
    regions[bi] = unite(regions[bi], regions[bj]);
    regions.erase(regions.begin() + static_cast<std::ptrdiff_t>(bj));
  }
}
}  // namespace

Renderer::DrawnDraw Renderer::drawn_state(std::size_t i) const {
  const GpuDraw& d = *draws_[i];
  const auto node_index = static_cast<std::size_t>(d.item->node);
  const Node& node = scene_.nodes[node_index];
  const Material& mat = scene_.materials[static_cast<std::size_t>(d.prim->material)];
  const auto mi = static_cast<std::size_t>(d.prim->material);
  DrawnDraw s;
  s.visible = visible_[node_index] != 0;
  s.world = world_[node_index];
  s.base = outputs_.base_color.size() > mi && outputs_.base_color[mi] ? *outputs_.base_color[mi] : mat.base_color;
  s.emissive = outputs_.emissive.size() > mi && outputs_.emissive[mi] ? *outputs_.emissive[mi] : mat.emissive;
  if (node.skin >= 0) {
    for (int j : scene_.skins[static_cast<std::size_t>(node.skin)].joints) {
      const glm::mat4& jw = world_[static_cast<std::size_t>(j)];
      s.deform.insert(s.deform.end(), &jw[0][0], &jw[0][0] + 16);
    }
  }
  if (d.prim->morph_targets > 0) {
    s.deform.insert(s.deform.end(), pose_.weights[node_index].begin(), pose_.weights[node_index].end());
    for (const auto& m : outputs_.morph)
      if (m.node == d.item->node) s.deform.insert(s.deform.end(), {float(m.target), m.weight});
  }
  return s;
}

std::vector<Renderer::DrawnText> Renderer::visible_texts() {
  std::vector<DrawnText> out;
  for (const auto& t : outputs_.texts) {
    if (!drawable(t, visible_)) continue;
    platform::TextRenderer& tr = text_renderer(t.size_px);
    const glm::vec2 p = project(t.node);
    const int x = static_cast<int>(std::lround(p.x)), y = static_cast<int>(std::lround(p.y));
    platform::Rect ink;
    try {
      ink = tr.measure(t.text, x, y, to_platform(t.align));
    } catch (const platform::TextError&) {
      ink = tr.measure("?", x, y, to_platform(t.align));
    }
    // 2 px: glyph quads are placed at whole pixels but their edges are antialiased (linear filter).
    constexpr int kPad = 2;
    PixelRegion box;
    if (!ink.empty())
      box = {ink.x - kPad, height_ - (ink.y + ink.height) - kPad, ink.width + 2 * kPad, ink.height + 2 * kPad};
    out.push_back({t, box});
  }
  return out;
}

std::optional<PixelRegion> Renderer::screen_box(const Primitive& prim, const glm::mat4& world, const glm::mat4& vp) const {
  const glm::mat4 m = vp * world;
  float x0 = std::numeric_limits<float>::max(), y0 = x0, x1 = -x0, y1 = -x0;
  for (int k = 0; k < 8; ++k) {
    const glm::vec3 p((k & 1) ? prim.bounds_max.x : prim.bounds_min.x, (k & 2) ? prim.bounds_max.y : prim.bounds_min.y,
                      (k & 4) ? prim.bounds_max.z : prim.bounds_min.z);
    const glm::vec4 c = m * glm::vec4(p, 1.0f);
    if (!(c.w > 1e-6f)) return std::nullopt;
    const float sx = (c.x / c.w * 0.5f + 0.5f) * float(width_), sy = (c.y / c.w * 0.5f + 0.5f) * float(height_);
    if (!std::isfinite(sx) || !std::isfinite(sy)) return std::nullopt;
    x0 = std::min(x0, sx), x1 = std::max(x1, sx), y0 = std::min(y0, sy), y1 = std::max(y1, sy);
  }
  // Pixels are covered by their centre (and MSAA samples inside them): floor/ceil plus 1 px.
  const float lim = 4.0f * float(std::max(width_, height_));
  x0 = std::clamp(x0, -lim, lim), x1 = std::clamp(x1, -lim, lim), y0 = std::clamp(y0, -lim, lim), y1 = std::clamp(y1, -lim, lim);
  const int ix0 = int(std::floor(x0)) - 1, iy0 = int(std::floor(y0)) - 1;
  const int ix1 = int(std::ceil(x1)) + 1, iy1 = int(std::ceil(y1)) + 1;
  return PixelRegion{ix0, iy0, ix1 - ix0, iy1 - iy0};
}

bool Renderer::outside(const GpuDraw& d, const PixelRegion& scissor, const glm::mat4& vp) const {
  auto misses = [&](const GpuDraw& one) {
    const Node& node = scene_.nodes[static_cast<std::size_t>(one.item->node)];
    if (node.skin >= 0 || one.prim->morph_targets > 0) return false;  // bounds unknown: draw it
    const auto b = screen_box(*one.prim, world_[static_cast<std::size_t>(one.item->node)], vp);
    return b && !overlap(*b, scissor);
  };
  if (!d.group) return misses(d);
  for (const auto& m : d.group->members)
    if (m.visible && !misses(*m.draw)) return false;
  return true;
}

Renderer::Snapshot Renderer::snapshot() {
  Snapshot now;
  now.draws.reserve(draws_.size());
  for (std::size_t i = 0; i < draws_.size(); ++i) now.draws.push_back(drawn_state(i));
  now.texts = visible_texts();
  return now;
}

std::optional<std::vector<PixelRegion>> Renderer::damage(const glm::mat4& vp, const Snapshot& now_state) {
  if (!options_.partial_redraw || !drawn_valid_ || vp != drawn_vp_) return std::nullopt;
  // A light that moved or changed lights every pixel.
  for (const auto& [node, world] : drawn_lights_)
    if (world_[static_cast<std::size_t>(node)] != world) return std::nullopt;

  std::vector<PixelRegion> regions;
  // Screen box of a draw's bounds under `world`; false when a corner is at or behind the eye
  // (no finite box: redraw everything).
  auto box = [&](const GpuDraw& d, const glm::mat4& world) -> bool {
    const auto b = screen_box(*d.prim, world, vp);
    if (b) regions.push_back(*b);
    return b.has_value();
  };
  for (std::size_t i = 0; i < draws_.size(); ++i) {
    const DrawnDraw& now = now_state.draws[i];
    const DrawnDraw& was = drawn_draws_[i];
    if (now == was) continue;
    // Skinned or morphed geometry leaves the primitive's bounds.
    if (!now.deform.empty() && now.deform != was.deform) return std::nullopt;
    if (was.visible && !box(*draws_[i], was.world)) return std::nullopt;
    if (now.visible && !box(*draws_[i], now.world)) return std::nullopt;
  }
  const std::vector<DrawnText>& texts = now_state.texts;
  for (const auto& t : drawn_texts_)
    if (std::find(texts.begin(), texts.end(), t) == texts.end()) regions.push_back(t.box);
  for (const auto& t : texts)
    if (std::find(drawn_texts_.begin(), drawn_texts_.end(), t) == drawn_texts_.end()) regions.push_back(t.box);

  normalise(regions, width_, height_);
  long long total = 0;
  for (const auto& r : regions) total += area(r);
  // Past half the target, scissored passes save little and cost extra passes: draw it all.
  if (2 * total > static_cast<long long>(width_) * height_) return std::nullopt;
  return regions;
}

void Renderer::remember_drawn(const glm::mat4& vp, Snapshot now) {
  drawn_vp_ = vp;
  drawn_draws_ = std::move(now.draws);
  drawn_texts_ = std::move(now.texts);
  drawn_lights_ = light_worlds();
  drawn_valid_ = true;
}

std::vector<std::pair<int, glm::mat4>> Renderer::light_worlds() const {
  std::vector<std::pair<int, glm::mat4>> out;
  for (int n : light_nodes_) out.emplace_back(n, world_[static_cast<std::size_t>(n)]);
  return out;
}

bool Renderer::layer_current(const glm::mat4& vp, const Snapshot& now) const {
  if (!layer_ || !layer_valid_ || vp != layer_vp_ || light_worlds() != layer_lights_) return false;
  // Static by the scene's description; checked anyway, so a misjudged draw costs a rebuild, never a
  // stale pixel.
  for (std::size_t i = 0; i < draws_.size(); ++i)
    if (!draws_[i]->changeable && !(now.draws[i] == layer_draws_[i])) return false;
  return true;
}

void Renderer::build_layer(const glm::mat4& vp, const Snapshot& now) {
  if (!layer_) {
    platform::RenderTargetOptions rt;
    rt.width = width_, rt.height = height_, rt.samples = target_->samples(), rt.depth = target_->depth();
    layer_ = std::make_unique<platform::RenderTarget>(backend_, rt);
  }
  draw_scene(*layer_, nullptr, DrawSet::StaticOpaque);
  layer_vp_ = vp;
  layer_draws_ = now.draws;
  layer_lights_ = light_worlds();
  layer_valid_ = true;
  ++stats_.layer_builds;
}

void Renderer::resolve_pending() {
  // Many small resolves cost more than one full one; past 16, resolve everything.
  if (unresolved_.size() > 16) unresolved_ = {PixelRegion{0, 0, width_, height_}};
  target_->resolve(unresolved_);
  unresolved_.clear();
}

FrameTiming Renderer::render(bool force, bool read_back) {
  FrameTiming t;
  ++stats_.frames;
  auto t0 = Clock::now();
  update_world();
  t.update_ms = ms_since(t0);
  // A skipped frame still answers a read with the frame that stands.
  auto skip = [&] {
    ++stats_.skipped;
    if (read_back) {
      auto t2 = Clock::now();
      read();
      t.gpu_readback_ms = ms_since(t2);
    }
    return t;
  };
  if (!dirty_ && !force) return skip();
  auto t1 = Clock::now();
  const glm::mat4 vp = view_projection(nullptr);
  // What every draw and text looks like now: compared with the last drawn frame, then remembered.
  Snapshot now = snapshot();
  auto regions = force ? std::nullopt : damage(vp, now);
  // The static layer: used by unforced frames (a forced frame is drawn from scratch), where the
  // backend can copy multisample pixels and the scene makes it worth keeping (classify_draws).
  const bool layered = !force && options_.partial_redraw && options_.static_layer && gl_.info.has_copy_image &&
                       layer_pays_;
  const bool layer_ok = layered && layer_current(vp, now);
  if (layered && !layer_ok) regions = std::nullopt;  // the layer must be redrawn: a full frame
  if (regions && regions->empty()) {
    // Inputs changed but no pixel can have (e.g. a hidden node's text): the frame stands.
    t.submit_ms = ms_since(t1);
    dirty_ = false;
    return skip();
  }
  if (!regions) {
    if (layered) {
      if (!layer_ok) build_layer(vp, now);
      const platform::PixelRegion all{0, 0, width_, height_};
      target_->copy_from(*layer_, std::span<const platform::PixelRegion>(&all, 1));
      draw_scene(*target_, nullptr, DrawSet::OverStatic);
    } else {
      draw_scene(*target_, nullptr, DrawSet::Everything);
    }
    draw_text();
    unresolved_ = {platform::PixelRegion{0, 0, width_, height_}};
    t.redrawn_fraction = 1.0;
  } else {
    long long pixels = 0;
    if (layered) target_->copy_from(*layer_, *regions);
    for (const auto& r : *regions) {
      draw_scene(*target_, &r, layered ? DrawSet::OverStatic : DrawSet::Everything);
      draw_text();
      pixels += area(r);
    }
    gl_.Disable(GL_SCISSOR_TEST);
    unresolved_.insert(unresolved_.end(), regions->begin(), regions->end());
    t.redrawn_fraction = double(pixels) / (double(width_) * double(height_));
    t.regions = static_cast<int>(regions->size());
    ++stats_.partial_frames;
  }
  remember_drawn(vp, std::move(now));
  t.submit_ms = ms_since(t1);
  auto t2 = Clock::now();
  gl_.Finish();
  if (read_back) read();
  t.gpu_readback_ms = ms_since(t2);
  platform::check_gl(gl_, scene_.source_name + ": drawing a frame");
  t.drawn = true;
  dirty_ = false;
  ++stats_.drawn;
  stats_.redrawn_fraction_sum += t.redrawn_fraction;
  return t;
}

const platform::Image& Renderer::read() {
  resolve_pending();
  image_ = target_->read_resolved();
  return image_;
}

}  // namespace meter::engine
