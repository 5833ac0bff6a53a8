// glTF import: load the file with tinygltf (syntax, buffers, image decoding), then validate every
// element, used or not, collecting all errors so an artist sees them at once. Each element kind is
// validated by the stage that converts it; this file fixes the order the messages come in.
#include <stb_image.h>

#include <set>

#include "convert_context.hpp"

namespace meter::convert {

namespace {

// The largest image side a texture may have. GLES 3.0 guarantees 2048 and cluster GPUs commonly
// take 4096; a 4096 x 4096 RGBA image already costs 64 MB decoded, and the decoder may allocate an
// image's whole size from its header alone (a 68-byte PNG can claim 16000 x 16000 = 1 GB).
constexpr int kMaxImageSide = 4096;

// tinygltf's image loader, after reading the size from the image header: an image larger than
// kMaxImageSide on either side is refused before any pixel is allocated.
bool load_image_within_limit(tinygltf::Image* image, int index, std::string* err, std::string* warn, int req_width,
                             int req_height, const unsigned char* bytes, int size, void* user_data) {
  int w = 0, h = 0, components = 0;
  if (stbi_info_from_memory(bytes, size, &w, &h, &components) && (w > kMaxImageSide || h > kMaxImageSide)) {
    if (err) {
      *err += "images[" + std::to_string(index) + "]: " + std::to_string(w) + " x " + std::to_string(h) +
              " pixels, more than the " + std::to_string(kMaxImageSide) + " x " + std::to_string(kMaxImageSide) +
              " a texture may have\n";
    }
    return false;
  }
  return tinygltf::LoadImageData(image, index, err, warn, req_width, req_height, bytes, size, user_data);
}

}  // namespace

tinygltf::Model load_gltf(const std::string& path) {
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&load_image_within_limit, nullptr);
  std::string err, warn;
  const bool binary = path.size() >= 4 && (path.compare(path.size() - 4, 4, ".glb") == 0 || path.compare(path.size() - 4, 4, ".GLB") == 0);
  bool ok = false;
  try {
    ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path) : loader.LoadASCIIFromFile(&model, &err, &warn, path);
  } catch (const std::exception& e) {
    err = e.what();
  }
  if (!ok) {
    while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
    throw SceneError(path + ": cannot load glTF: " + (err.empty() ? "unknown tinygltf error" : err));
  }
  return model;
}

void validate_gltf(ConvertContext& ctx) {
  static const std::set<std::string> supported{"KHR_lights_punctual", "KHR_materials_unlit", "KHR_texture_transform",
                                               "KHR_materials_emissive_strength", "KHR_mesh_quantization"};
  for (std::size_t i = 0; i < ctx.m.extensionsRequired.size(); ++i) {
    if (!supported.count(ctx.m.extensionsRequired[i])) {
      ctx.error(idx("extensionsRequired", i), "extension " + ctx.m.extensionsRequired[i] + " is required by the file but not supported");
    }
  }
  ctx.accessor_ok.assign(ctx.m.accessors.size(), 0);
  ctx.accessor_values.assign(ctx.m.accessors.size(), {});
  for (std::size_t i = 0; i < ctx.m.accessors.size(); ++i) check_accessor(ctx, i);
  validate_nodes(ctx);
  for (std::size_t i = 0; i < ctx.m.meshes.size(); ++i) validate_mesh(ctx, i);
  for (std::size_t i = 0; i < ctx.m.skins.size(); ++i) validate_skin(ctx, i);
  for (std::size_t i = 0; i < ctx.m.animations.size(); ++i) validate_animation(ctx, i);
  for (std::size_t i = 0; i < ctx.m.materials.size(); ++i) validate_material(ctx, i);
  validate_textures(ctx);
  validate_cameras(ctx);
  validate_lights(ctx);
  const int scene = ctx.m.defaultScene >= 0 ? ctx.m.defaultScene : 0;
  if (!ctx.m.scenes.empty() && static_cast<std::size_t>(scene) >= ctx.m.scenes.size()) ctx.error("scene", "index out of range");
  else if (!ctx.m.scenes.empty()) validate_environment(ctx, static_cast<std::size_t>(scene));
  for (std::size_t s = 0; s < ctx.m.scenes.size(); ++s) {
    for (int n : ctx.m.scenes[s].nodes) {
      if (n < 0 || static_cast<std::size_t>(n) >= ctx.m.nodes.size()) ctx.error(idx("scenes", s) + ".nodes", "node index " + std::to_string(n) + " out of range");
      else if (ctx.parent[static_cast<std::size_t>(n)] >= 0) ctx.error(idx("scenes", s) + ".nodes", "node " + std::to_string(n) + " is not a root node");
    }
  }
}

}  // namespace meter::convert
