// GPU resources of a scene: programs with their uniform and sampler locations, textures, one
// vertex/index buffer pair per primitive and a VAO per draw, and the merged groups' dynamic
// buffers (world-space vertices of every member, indices of the visible ones).
#pragma once

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "meter/engine/evaluation/frame_state.hpp"
#include "meter/engine/evaluation/skinned_normals.hpp"
#include "meter/engine/vocabulary.hpp"
#include "meter/platform/gl_api.hpp"
#include "meter/platform/program_cache.hpp"

namespace meter::engine {

struct RendererStats;
class ProgramBinaryCache;  // meter/engine/gl/program_binary_cache.hpp

struct GpuProgram {
  GLuint program = 0;  // 0 until compiled (a cheaper level's program: when a frame first uses it)
  std::string label;
  const bridge::Program* info = nullptr;
  struct Uniform {
    GLint location = -1;
    bridge::UniformSemantic semantic{};
    int index = -1, array_size = 1;
  };
  std::vector<Uniform> uniforms;
  struct Sampler {
    GLint location = -1;
    bridge::TextureSlot slot{};
    int unit = 0;
    int index = -1;  // ShadowMap: the light's light_order index
  };
  std::vector<Sampler> samplers;
};

struct GpuGroup;

// One program's view of a vertex buffer: its VAO, and the constant values of the attributes the
// buffer lacks (set before the draw).
struct GpuVertexInput {
  GLuint vao = 0;
  std::vector<std::pair<GLuint, glm::vec4>> constant_attributes;
};

// One shading level of a draw (meter/bridge/draw_levels.hpp): [0] its own program.
struct GpuShading {
  GpuProgram* program = nullptr;
  // The program generated for this level: blend and cull state, and (uber mode) the switches.
  const bridge::Program* shape = nullptr;
  const ShadingLevel* level = nullptr;  // null: level 0, the material's own parameters
  GpuVertexInput input;                 // drawn on its own
  bool flat_lists = false;              // a Flat program on a primitive with Flat lists: draws those
};

struct GpuDraw {
  const DrawItem* item = nullptr;
  const Primitive* prim = nullptr;
  std::vector<GpuShading> shadings;  // per DrawState::shading
  // Per DrawState::lod: byte offset of its index list in the primitive's index buffer, and count.
  std::vector<std::pair<std::uintptr_t, GLsizei>> lods;
  // The same per LOD for the primitive's Flat lists (Primitive::flat_indices); empty without.
  std::vector<std::pair<std::uintptr_t, GLsizei>> flat_lods;
  // The index lists a shading level draws, per LOD.
  const std::vector<std::pair<std::uintptr_t, GLsizei>>& lists(const GpuShading& sh) const { return sh.flat_lists ? flat_lods : lods; }
  GpuGroup* group = nullptr;  // set on a merged group's representative only
};

// One merged group: world-space vertices of every member in one dynamic buffer, indices of the
// visible members only (each member's list at its LOD). Member ranges are rewritten only when that
// member's world matrix or visibility changed, so a static scene costs nothing per frame.
struct GpuGroup {
  GLuint vbo = 0, ebo = 0;
  std::vector<GpuVertexInput> inputs;  // per shading level of the representative
  std::vector<float> vertices;
  std::vector<std::uint32_t> indices;
  GLsizei index_count = 0;
  struct Member {
    const GpuDraw* draw = nullptr;
    std::uint32_t first_vertex = 0;
    glm::mat4 world{0.0f};
    bool uploaded = false, mirrored = false;
    char visible = -1;
    int lod = 0;  // the LOD its indices were built at
    bool flat = false;  // whether they are its Flat lists
  };
  std::vector<Member> members;
};

// A skinned draw whose normals follow the deformed surface (skinned_normals.hpp): its own vertex
// buffer (instances of one mesh bend apart), rewritten when its joints move.
struct GpuSkinnedDraw {
  const GpuDraw* draw = nullptr;
  GLuint vbo = 0;
  SkinnedNormalsLayout layout;
  std::vector<float> vertices;   // the primitive's records with the current normals
  std::vector<glm::mat4> joints;  // the joint matrices they were computed for (empty: never)
};

class GpuScene {
 public:
  // `uber_shader`: every draw goes through this one program (benchmark baseline), else the
  // package's generated programs. `merged`: the merged groups get their buffers.
  // `programs` (may be null: the scene links its own) lends programs linked for the same sources
  // by an earlier scene on this context, and must outlive this. `binaries` (may be null; used
  // where `programs` is null) keeps the linked programs across runs, and must outlive this.
  GpuScene(const platform::Gl& gl, const Scene& scene, const bridge::Program* uber_shader, bool merged,
           platform::ProgramCache* programs = nullptr, ProgramBinaryCache* binaries = nullptr);
  ~GpuScene();
  GpuScene(const GpuScene&) = delete;
  GpuScene& operator=(const GpuScene&) = delete;

  // Compiles the programs of the shading levels `frame` draws with that are not compiled yet.
  void prepare(const FrameState& frame);
  // Brings the merged groups' buffers to the frame's world matrices, visibility and LODs.
  void update_groups(const FrameState& frame, RendererStats& stats);
  // Brings the skinned draws' normals to the frame's pose (a draw whose joints did not move costs
  // one comparison).
  void update_skinned(const FrameState& frame, RendererStats& stats);

  // With shadow maps (`depth_variants`): compiles the depth-only variant of every program `frame`
  // draws with that has none yet.
  void prepare_depth(const FrameState& frame);
  // The depth-only variant of `program` (its vertex shader, an empty fragment shader: what a shadow
  // map's pass needs); null before prepare_depth compiled it.
  const GpuProgram* depth_program(const GpuProgram* program) const;

  // Programs linked so far (compiled or from kept binaries) and the wall time that took.
  std::size_t programs_linked() const { return programs_linked_; }
  double program_link_ms() const { return program_link_ms_; }

  const std::vector<std::unique_ptr<GpuDraw>>& draws() const { return draws_; }
  GLuint texture(int index) const { return index >= 0 ? textures_[static_cast<std::size_t>(index)] : white_texture_; }
  // The scene's reflection probe (a cube map), 0 without an environment.
  GLuint environment_probe() const { return environment_probe_; }

 private:
  void add_program(const bridge::Program& p, const std::string& label, bool compile_now);
  // `fragment_source`: empty for the program's own, else the one to link with its vertex shader.
  void compile(GpuProgram& program, const std::string& fragment_source = {});
  void upload_textures();
  void upload_environment_probe();
  void build_draws(bool uber);
  void build_groups();
  // A VAO binding `program`'s attributes to `layout` in the bound vertex / index buffers;
  // `merged`: the merged record (layout + vertex alpha, merged_stride).
  GpuVertexInput vertex_input(const GpuProgram& program, const Primitive& layout, bool merged, GLuint vbo, GLuint ebo);

  const platform::Gl& gl_;
  platform::ProgramCache* program_cache_ = nullptr;
  ProgramBinaryCache* binaries_ = nullptr;
  std::size_t programs_linked_ = 0;
  double program_link_ms_ = 0.0;
  const Scene& scene_;
  std::vector<std::unique_ptr<GpuProgram>> programs_;
  std::map<const GpuProgram*, std::unique_ptr<GpuProgram>> depth_programs_;
  std::vector<std::unique_ptr<GpuDraw>> draws_;
  std::vector<std::unique_ptr<GpuGroup>> groups_;
  std::vector<GpuSkinnedDraw> skinned_;
  std::vector<GLuint> textures_;
  GLuint white_texture_ = 0;
  GLuint environment_probe_ = 0;
  std::vector<GLuint> buffers_;
};

}  // namespace meter::engine
