// The texts' font, read at conversion time for the package (meter/convert/scene_font.hpp).
#include "meter/convert/scene_font.hpp"

#include <fstream>
#include <iterator>

#include "meter/platform/text.hpp"

namespace meter::convert {

namespace fs = std::filesystem;

SceneFont read_font_file(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw SceneError("font '" + file.string() + "': cannot open it");
  SceneFont font;
  font.name = file.filename().string();
  font.data.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (in.bad()) throw SceneError("font '" + file.string() + "': read failed");
  try {
    platform::check_font({file.string(), font.data});
  } catch (const platform::TextError& e) {
    throw SceneError(e.what());
  }
  return font;
}

SceneFont load_scene_font(const SceneConfig& config, const FontSearch& search) {
  if (!config_draws_text(config)) return {};
  std::error_code ec;
  if (!config.font.empty()) {
    // Relative to the config file, as the artist writes it beside the scene.
    const fs::path named = fs::path(config.origin).parent_path() / config.font;
    if (!fs::is_regular_file(named, ec))
      throw SceneError(config.origin + ": $.font: font file '" + config.font + "' not found (looked for " +
                       fs::absolute(named, ec).string() + ")");
    return read_font_file(named);
  }
  std::string looked;
  for (const fs::path& folder : search.folders) {
    const fs::path candidate = folder / search.file;
    if (fs::is_regular_file(candidate, ec)) return read_font_file(candidate);
    looked += (looked.empty() ? "" : ", ") + folder.string();
  }
  throw SceneError(config.origin + ": the scene's texts need the font " + search.file + ", which is not installed (looked in " +
                   (looked.empty() ? std::string("no folder") : looked) +
                   "; it comes with the Debian package fonts-dejavu-core), or name a font file in the config's \"font\"");
}

}  // namespace meter::convert
