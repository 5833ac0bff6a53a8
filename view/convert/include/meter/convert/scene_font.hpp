// The font a scene's texts are drawn with, found and read at conversion time so that it travels in
// the package (Scene::font, chunk FONT) and the view opens no font file: the file the scene
// config's "font" names (relative to the config file), else DejaVu Sans from fonts-dejavu-core.
// A scene that draws no text (bridge::config_draws_text) gets no font and needs none.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "meter/convert/vocabulary.hpp"

namespace meter::convert {

// Where the default font is looked for: the file name in each folder in turn.
struct FontSearch {
  std::string file = "DejaVuSans.ttf";
  // Where the Debian package fonts-dejavu-core installs it.
  std::vector<std::filesystem::path> folders = {"/usr/share/fonts/truetype/dejavu"};
};

// The whole file as a SceneFont named by its file name, checked to open in FreeType as a scalable
// font. Throws SceneError naming the file (unreadable, not a font).
SceneFont read_font_file(const std::filesystem::path& file);

// The font `config`'s texts need, or an empty SceneFont when it draws none. Throws SceneError
// naming the config file, the font and where it was looked for when it is missing.
SceneFont load_scene_font(const SceneConfig& config, const FontSearch& search = {});

}  // namespace meter::convert
