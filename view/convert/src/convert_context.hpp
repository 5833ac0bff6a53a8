// What the conversion stages of the data converter share (private to meter_convert): the loaded
// glTF, its accessors decoded to doubles, the node hierarchy validation found, the environment
// image named in the scene's extras, and the diagnostics collected along the way.
//
// The stages run in this order (convert_gltf.cpp): load (gltf_import.cpp), validate every element
// (each stage's validate_* function, called from gltf_import.cpp), then build the Scene: materials,
// textures, environment, meshes, cameras and lights, skins, nodes, animations, the config check,
// the mesh concatenation plan and the generated programs.
#pragma once

#include <array>
#include <initializer_list>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <tiny_gltf.h>

#include "meter/convert/concat_plan.hpp"
#include "meter/convert/converter.hpp"
#include "meter/platform/image.hpp"

namespace meter::convert {

// "accessors[3]"
std::string idx(const char* what, std::size_t i);
// A number in a message: 6 significant digits.
std::string fmt(double v);

// The world image Blender lit the scene with (the default scene's `meter_environment` extras).
struct EnvironmentSource {
  platform::Image image;  // decoded equirectangular PNG (empty = none)
  float strength = 1.0f;
  std::string name;       // file name as written in the extras
};

struct ConvertContext {
  ConvertContext(const tinygltf::Model& model, std::string path, const SceneConfig& config, const ConvertOptions& options)
      : m(model), file(std::move(path)), cfg(config), opt(options) {}

  const tinygltf::Model& m;
  std::string file;
  const SceneConfig& cfg;
  ConvertOptions opt;
  std::vector<Diagnostic> errors, repairs;
  std::vector<char> accessor_ok;                     // per accessor: passed validation
  std::vector<std::vector<double>> accessor_values;  // per accessor: decoded components
  std::vector<int> parent;                           // per node: its parent, -1 for a root
  EnvironmentSource environment;
  ConcatPlan plan;               // mesh concatenation groups
  std::set<int> group_members;   // nodes merged at runtime: their programs get vertex_alpha

  void error(const std::string& path, const std::string& msg) { errors.push_back({path, msg}); }
  void repair(const std::string& path, const std::string& msg) { repairs.push_back({path, msg}); }

  // Validated accessor `a` used as `path`, with an expected type; returns nullptr (after an error)
  // when unusable (accessors.cpp).
  const std::vector<double>* use_accessor(int a, const std::string& path, std::initializer_list<int> types,
                                          std::initializer_list<int> component_types);
  // An accessor flattened to `comps_out` floats per element (missing components = 1), optionally
  // clamped to 0..1 (the repair validation announced for colours).
  std::vector<float> attribute(int acc, int comps_out, bool clamp01 = false) const;
};

// ---- load and validation (gltf_import.cpp, accessors.cpp and the stage files)
tinygltf::Model load_gltf(const std::string& path);  // throws SceneError
void validate_gltf(ConvertContext& c);               // fills c.errors / c.repairs

int component_size(int component_type);  // bytes; 0 when unsupported
int type_components(int type);           // SCALAR 1 .. MAT4 16; 0 when unsupported
const char* type_name(int type);
void check_accessor(ConvertContext& c, std::size_t i);  // validates and decodes accessors[i]

void validate_nodes(ConvertContext& c);
void validate_mesh(ConvertContext& c, std::size_t mesh);
void validate_skin(ConvertContext& c, std::size_t skin);
void validate_animation(ConvertContext& c, std::size_t animation);
void validate_material(ConvertContext& c, std::size_t material);
void validate_textures(ConvertContext& c);
void validate_cameras(ConvertContext& c);
void validate_lights(ConvertContext& c);
bool casts_shadow(const tinygltf::Light& l);  // extras.meter_cast_shadow true (lights_cameras.cpp)
void validate_environment(ConvertContext& c, std::size_t scene);

// ---- conversion of validated elements into the Scene (one stage per file)
// materials.cpp: every glTF material, then the glTF default material; returns the default's index.
// texture_srgb[t] ends as 1 (colour), 0 (data) or -1 (unused) for each glTF texture.
int convert_materials(ConvertContext& c, Scene& s, std::vector<int>& texture_srgb);
void convert_textures(const ConvertContext& c, const std::vector<int>& texture_srgb, Scene& s);  // textures.cpp
void convert_environment(const ConvertContext& c, Scene& s);                                     // environment.cpp
void convert_meshes(ConvertContext& c, int default_material, Scene& s);                          // primitives.cpp
void convert_cameras(const ConvertContext& c, Scene& s);                                         // lights_cameras.cpp
void convert_lights(const ConvertContext& c, Scene& s);                                          // lights_cameras.cpp
void convert_skins(const ConvertContext& c, Scene& s);                                           // skins.cpp
void convert_nodes(const ConvertContext& c, Scene& s);                                           // nodes.cpp
void convert_animations(const ConvertContext& c, Scene& s);                                      // animations.cpp
void generate_programs(const ConvertContext& c, Scene& s);                                       // programs.cpp

// nodes.cpp: the KHR_lights_punctual light index of nodes[i]; -1 none, -2 not a number.
int node_light(const tinygltf::Model& m, std::size_t i);
// nodes.cpp: a glTF column-major matrix as TRS; false (with the reason) when it has a projective
// row, a zero scale axis or shear.
bool decompose(const std::vector<double>& matrix, glm::vec3& t, glm::quat& r, glm::vec3& s, std::string& why);

// environment.cpp: EEVEE's world ambient cube of an equirectangular map (one linear radiance per
// signed axis +X -X +Y -Y +Z -Z), scaled by `strength`.
std::array<glm::vec3, 6> ambient_cube(const platform::Image& image, float strength);

}  // namespace meter::convert
