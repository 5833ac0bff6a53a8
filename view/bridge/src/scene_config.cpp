// Names and number formats of the scene config vocabulary, shared by the converter (which
// validates formats) and the runtime (which formats the numbers a text binding shows), and whether
// a config draws text (which needs the package's font).
#include "meter/bridge/scene_config.hpp"

#include <algorithm>
#include <string>
#include <string_view>
#include <cstdio>

namespace meter::bridge {

const char* to_string(BindingKind kind) {
  switch (kind) {
    case BindingKind::Animation: return "animation";
    case BindingKind::Visibility: return "visibility";
    case BindingKind::Emissive: return "emissive";
    case BindingKind::Color: return "color";
    case BindingKind::Morph: return "morph";
    case BindingKind::Text: return "text";
  }
  return "?";
}

bool config_draws_text(const SceneConfig& config) {
  const bool binding = std::any_of(config.bindings.begin(), config.bindings.end(),
                                   [](const Binding& b) { return b.kind == BindingKind::Text; });
  const bool script = std::any_of(config.scripts.begin(), config.scripts.end(), [](const Script& s) {
    return std::any_of(s.outputs.begin(), s.outputs.end(),
                       [](const ScriptOutput& o) { return o.kind == ScriptOutputKind::Text; });
  });
  return binding || script || !config.link_loss.text_node.empty();
}

bool valid_number_format(std::string_view f, std::string* why) {
  int conversions = 0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (f[i] != '%') continue;
    ++i;
    if (i < f.size() && f[i] == '%') continue;
    while (i < f.size() && std::string_view("-+ #0").find(f[i]) != std::string_view::npos) ++i;
    int width_digits = 0;
    while (i < f.size() && f[i] >= '0' && f[i] <= '9') ++i, ++width_digits;
    if (i < f.size() && f[i] == '.') {
      ++i;
      int prec_digits = 0;
      while (i < f.size() && f[i] >= '0' && f[i] <= '9') ++i, ++prec_digits;
      if (prec_digits > 2) width_digits = 99;
    }
    if (width_digits > 2) {
      if (why) *why = "width/precision must be at most two digits";
      return false;
    }
    if (i >= f.size() || std::string_view("feEgGF").find(f[i]) == std::string_view::npos) {
      if (why) *why = "only %f %e %g (with flags, width, precision) and %% are allowed in \"" + std::string(f) + "\"";
      return false;
    }
    ++conversions;
  }
  if (conversions != 1) {
    if (why) *why = "expected exactly one number conversion (e.g. \"%.0f km\") in \"" + std::string(f) + "\"";
    return false;
  }
  return true;
}

std::string format_number(const std::string& format, double value) {
  char buf[256];
  // The format was checked by valid_number_format (one float conversion, widths <= 99).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
  int n = std::snprintf(buf, sizeof buf, format.c_str(), value);
#pragma GCC diagnostic pop
  if (n < 0) return {};
  return std::string(buf, static_cast<std::size_t>(std::min<int>(n, sizeof buf - 1)));
}

}  // namespace meter::bridge
