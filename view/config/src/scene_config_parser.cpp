// The scene config parser. Both sides run it: the converter on the artist's file, the runtime on
// the config text the package stores.
#include "meter/config/scene_config_parser.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "meter/protocol/catalog.hpp"
#include "scene_scripts_parser.hpp"
#include "config_json.hpp"
#include "scene_features_parser.hpp"

namespace meter::config {
using namespace meter::bridge;  // the vocabulary the parsers fill
namespace {

using nlohmann::json;
using namespace config_json;

// A text binding's own keys: the node, the number format, size, colour, alignment and the
// value -> text map.
void parse_text_binding(const Ctx& c, const json& b, const std::string& path, Binding& out) {
  out.node = string(c, b["node"], path + ".node");
  if (b.contains("format")) {
    out.format = string(c, b["format"], path + ".format");
    std::string why;
    if (!valid_number_format(out.format, &why)) c.fail(path + ".format", why);
  }
  if (b.contains("size_px")) {
    out.size_px = number(c, b["size_px"], path + ".size_px");
    if (out.size_px < 4 || out.size_px > 512) c.fail(path + ".size_px", "expected 4..512 pixels");
  }
  if (b.contains("color")) out.color = colour(c, b["color"], path + ".color");
  if (b.contains("colour")) out.color = colour(c, b["colour"], path + ".colour");
  if (b.contains("align")) out.align = parse_align(c, b["align"], path + ".align");
  if (b.contains("map")) {
    const json& m = b["map"];
    if (!m.is_object()) c.fail(path + ".map", "expected an object {\"value\": \"text\"}");
    for (auto it = m.begin(); it != m.end(); ++it) {
      const std::string kp = path + ".map." + it.key();
      long long k = 0;
      std::size_t used = 0;
      try {
        k = std::stoll(it.key(), &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != it.key().size()) c.fail(kp, "map keys must be integers");
      out.map[k] = string(c, it.value(), kp);
    }
  }
}

// The binding's look while the link is lost; `keys`: the failsafe keys its kind allows.
void parse_failsafe(const Ctx& c, const json& f, const std::string& path, const std::set<std::string>& keys, Binding& out) {
  const std::string fp = path + ".failsafe";
  if (!f.is_object()) c.fail(fp, "expected an object");
  check_keys(c, f, fp, keys);
  if (f.contains("value")) out.failsafe_value = number(c, f["value"], fp + ".value");
  if (f.contains("visible")) out.failsafe_visible = boolean(c, f["visible"], fp + ".visible");
  if (f.contains("text")) out.failsafe_text = string(c, f["text"], fp + ".text");
}

Binding parse_binding(const Ctx& c, const json& b, const std::string& path) {
  if (!b.is_object()) c.fail(path, "expected an object");
  Binding out;
  if (!b.contains("signal")) c.fail(path + ".signal", "missing (a catalog signal name)");
  out.signal_id = catalog_signal(c, b["signal"], path + ".signal", out.signal);
  if (!b.contains("kind")) c.fail(path + ".kind", "missing");
  std::string kind = string(c, b["kind"], path + ".kind");
  auto need = [&](const char* key) -> const json& {
    if (!b.contains(key)) c.fail(path + "." + key, "missing (required for kind \"" + kind + "\")");
    return b[key];
  };
  std::set<std::string> keys{"signal", "kind", "failsafe", "comment", "quantity", "imperial", "safety"};
  auto failsafe_keys = std::set<std::string>{"value"};
  if (kind == "animation") {
    out.kind = BindingKind::Animation;
    keys.insert({"animation", "input", "time", "smoothing_ms"});
    out.animation = string(c, need("animation"), path + ".animation");
    out.input = range(c, need("input"), path + ".input");
    out.has_input = true;
    out.time = numbers<2>(c, need("time"), path + ".time");
  } else if (kind == "visibility") {
    out.kind = BindingKind::Visibility;
    keys.insert({"node", "threshold", "invert"});
    failsafe_keys.insert("visible");
    out.node = string(c, need("node"), path + ".node");
    if (b.contains("invert")) out.invert = boolean(c, b["invert"], path + ".invert");
  } else if (kind == "emissive" || kind == "color" || kind == "colour") {
    out.kind = kind == "emissive" ? BindingKind::Emissive : BindingKind::Color;
    keys.insert({"material", "off", "on", "input", "threshold", "smoothing_ms"});
    out.material = string(c, need("material"), path + ".material");
    out.off = colour(c, need("off"), path + ".off");
    out.on = colour(c, need("on"), path + ".on");
    if (b.contains("input")) {
      out.input = range(c, b["input"], path + ".input");
      out.has_input = true;
    }
  } else if (kind == "morph") {
    out.kind = BindingKind::Morph;
    keys.insert({"node", "target", "input", "weight", "smoothing_ms"});
    out.node = string(c, need("node"), path + ".node");
    double t = number(c, need("target"), path + ".target");
    if (t < 0 || t != std::floor(t) || t > 255) c.fail(path + ".target", "expected a morph target index 0..255");
    out.morph_target = static_cast<int>(t);
    out.input = range(c, need("input"), path + ".input");
    out.has_input = true;
    if (b.contains("weight")) out.weight = numbers<2>(c, b["weight"], path + ".weight");
  } else if (kind == "text") {
    out.kind = BindingKind::Text;
    keys.insert({"node", "format", "size_px", "color", "colour", "align", "map"});
    failsafe_keys = {"text"};
    need("node");
    parse_text_binding(c, b, path, out);
  } else {
    c.fail(path + ".kind",
           "unknown kind \"" + kind + "\" (expected animation, visibility, emissive, color, morph or text)");
  }
  if (b.contains("threshold")) out.threshold = number(c, b["threshold"], path + ".threshold");
  if (b.contains("safety")) out.safety = boolean(c, b["safety"], path + ".safety");
  if (b.contains("smoothing_ms")) {
    out.smoothing_ms = number(c, b["smoothing_ms"], path + ".smoothing_ms");
    if (out.smoothing_ms < 0 || out.smoothing_ms > 10000) c.fail(path + ".smoothing_ms", "expected 0..10000");
  }
  check_keys(c, b, path, keys);
  out.units = parse_binding_units(c, b, path, out.kind);
  if (b.contains("failsafe")) parse_failsafe(c, b["failsafe"], path, failsafe_keys, out);
  return out;
}

ResolveConfig parse_resolve(const Ctx& c, const json& r) {
  if (!r.is_object())
    c.fail("$.resolve", "expected an object {\"filter\": \"box\" | \"blackman-harris\", \"width_px\": 1.5, "
                        "\"sample_format\": \"srgb8\" | \"rgba16f\"}");
  check_keys(c, r, "$.resolve", {"filter", "width_px", "sample_format"});
  ResolveConfig out;
  if (r.contains("filter")) {
    const std::string f = string(c, r["filter"], "$.resolve.filter");
    if (f == "box") out.filter = ResolveConfig::Filter::Box;
    else if (f == "blackman-harris") out.filter = ResolveConfig::Filter::BlackmanHarris;
    else c.fail("$.resolve.filter", "unknown filter \"" + f + "\" (expected box or blackman-harris)");
  }
  if (r.contains("width_px")) {
    out.width_px = number(c, r["width_px"], "$.resolve.width_px");
    if (out.width_px < 0.5 || out.width_px > 3.0) c.fail("$.resolve.width_px", "expected 0.5 .. 3 pixels");
  }
  if (r.contains("sample_format")) {
    const std::string f = string(c, r["sample_format"], "$.resolve.sample_format");
    if (f == "srgb8") out.sample_format = ResolveConfig::SampleFormat::Srgb8;
    else if (f == "rgba16f") out.sample_format = ResolveConfig::SampleFormat::Rgba16f;
    else c.fail("$.resolve.sample_format", "unknown sample format \"" + f + "\" (expected srgb8 or rgba16f)");
  }
  return out;
}

// "off", one kind ("normal-maps", "mirrors"), or an array of kinds.
SampleShading parse_sample_shading(const Ctx& c, const json& v) {
  SampleShading out;
  const auto add = [&](const json& name, const std::string& path) {
    const std::string k = string(c, name, path);
    if (k == "normal-maps") out.normal_maps = true;
    else if (k == "mirrors") out.mirrors = true;
    else if (k != "off" || v.is_array())
      c.fail(path, "unknown value \"" + k + "\" (expected off, normal-maps, mirrors or an array of normal-maps and mirrors)");
  };
  if (!v.is_array()) {
    add(v, "$.sample_shading");
    return out;
  }
  for (std::size_t i = 0; i < v.size(); ++i) add(v[i], "$.sample_shading[" + std::to_string(i) + "]");
  return out;
}

// The render size in pixels, each side an integer 16..8192.
std::array<int, 2> parse_size(const Ctx& c, const json& v) {
  std::array<int, 2> size{};
  auto s = numbers<2>(c, v, "$.size");
  for (int i = 0; i < 2; ++i) {
    if (s[i] < 16 || s[i] > 8192 || s[i] != std::floor(s[i])) {
      c.fail("$.size[" + std::to_string(i) + "]", "expected an integer 16..8192");
    }
    size[i] = static_cast<int>(s[i]);
  }
  return size;
}

// The link-loss look: the failsafe text and where it is drawn.
void parse_link_loss(const Ctx& c, const json& l, LinkLossConfig& out) {
  if (!l.is_object()) c.fail("$.link_loss", "expected an object");
  check_keys(c, l, "$.link_loss", {"text_node", "text", "size_px", "color", "align"});
  if (l.contains("text_node")) out.text_node = string(c, l["text_node"], "$.link_loss.text_node");
  if (l.contains("text")) out.text = string(c, l["text"], "$.link_loss.text");
  if (l.contains("size_px")) out.size_px = number(c, l["size_px"], "$.link_loss.size_px");
  if (l.contains("color")) out.color = colour(c, l["color"], "$.link_loss.color");
  if (l.contains("align")) out.align = parse_align(c, l["align"], "$.link_loss.align");
}

// Mesh concatenation groups: a name and its member nodes each.
std::vector<Group> parse_groups(const Ctx& c, const json& gs) {
  std::vector<Group> groups;
  if (!gs.is_array()) c.fail("$.groups", "expected an array");
  for (std::size_t i = 0; i < gs.size(); ++i) {
    const std::string gp = "$.groups[" + std::to_string(i) + "]";
    if (!gs[i].is_object()) c.fail(gp, "expected an object");
    check_keys(c, gs[i], gp, {"name", "members"});
    Group g;
    if (!gs[i].contains("name")) c.fail(gp + ".name", "missing");
    g.name = string(c, gs[i]["name"], gp + ".name");
    if (!gs[i].contains("members") || !gs[i]["members"].is_array()) c.fail(gp + ".members", "expected an array of node names");
    for (std::size_t k = 0; k < gs[i]["members"].size(); ++k) {
      g.members.push_back(string(c, gs[i]["members"][k], gp + ".members[" + std::to_string(k) + "]"));
    }
    groups.push_back(std::move(g));
  }
  return groups;
}

// Per-material overrides by material name (the shading model).
std::map<std::string, MaterialOverride> parse_materials(const Ctx& c, const json& ms) {
  std::map<std::string, MaterialOverride> materials;
  if (!ms.is_object()) c.fail("$.materials", "expected an object {\"MaterialName\": {...}}");
  for (auto it = ms.begin(); it != ms.end(); ++it) {
    const std::string mp = "$.materials." + it.key();
    if (!it.value().is_object()) c.fail(mp, "expected an object");
    check_keys(c, it.value(), mp, {"shading"});
    MaterialOverride o;
    if (it.value().contains("shading")) {
      std::string s = string(c, it.value()["shading"], mp + ".shading");
      static const std::set<std::string> ok{"unlit", "flat", "gouraud", "blinn-phong", "pbr"};
      if (!ok.count(s)) c.fail(mp + ".shading", "expected unlit, flat, gouraud, blinn-phong or pbr");
      o.shading = s;
    }
    materials[it.key()] = o;
  }
  return materials;
}

}  // namespace

SceneConfig parse_scene_config(std::string_view text, const std::string& origin) {
  return parse_scene_config(text, *protocol::active_catalog(), origin);
}

SceneConfig parse_scene_config(std::string_view text, const protocol::Catalog& catalog, const std::string& origin) {
  Ctx c{origin, catalog};
  json j;
  try {
    j = json::parse(text.begin(), text.end());
  } catch (const json::exception& e) {  // parse_error, and out_of_range for a number overflow
    throw std::invalid_argument(origin + ": not valid JSON: " + e.what());
  }
  if (!j.is_object()) c.fail("$", "expected a JSON object");
  check_keys(c, j, "$",
             {"format", "size", "camera", "clear_color", "time", "ambient", "exposure", "bindings",
              "link_loss", "groups", "materials", "scripts", "comment", "pages", "theme", "units", "sweep", "resolve",
              "sample_shading", "font"});
  SceneConfig out;
  out.source_json = std::string(text);
  out.origin = origin;
  if (!j.contains("format")) c.fail("$.format", "missing (expected \"meter-scene-config/1\")");
  std::string format = string(c, j["format"], "$.format");
  if (format != "meter-scene-config/1") {
    c.fail("$.format", "unsupported format \"" + format + "\" (this build reads \"meter-scene-config/1\")");
  }
  if (j.contains("size")) out.size = parse_size(c, j["size"]);
  if (j.contains("camera")) out.camera = string(c, j["camera"], "$.camera");
  if (j.contains("clear_color")) out.clear_color = colour(c, j["clear_color"], "$.clear_color");
  if (j.contains("time")) {
    out.time = number(c, j["time"], "$.time");
  }
  if (j.contains("ambient")) out.ambient = numbers<3>(c, j["ambient"], "$.ambient");
  if (j.contains("exposure")) out.exposure = number(c, j["exposure"], "$.exposure");
  if (j.contains("bindings")) {
    const json& bs = j["bindings"];
    if (!bs.is_array()) c.fail("$.bindings", "expected an array");
    for (std::size_t i = 0; i < bs.size(); ++i) {
      out.bindings.push_back(parse_binding(c, bs[i], "$.bindings[" + std::to_string(i) + "]"));
    }
  }
  if (j.contains("resolve")) out.resolve = parse_resolve(c, j["resolve"]);
  if (j.contains("sample_shading")) out.sample_shading = parse_sample_shading(c, j["sample_shading"]);
  if (j.contains("link_loss")) parse_link_loss(c, j["link_loss"], out.link_loss);
  // The texts' font file: the converter embeds it in the package, the view never opens it.
  if (j.contains("font")) {
    out.font = string(c, j["font"], "$.font");
    if (out.font.empty()) c.fail("$.font", "expected a font file name (TrueType or OpenType), relative to the config file");
  }
  if (j.contains("groups")) out.groups = parse_groups(c, j["groups"]);
  if (j.contains("materials")) out.materials = parse_materials(c, j["materials"]);
  out.features = parse_scene_features(c, j);
  if (j.contains("scripts")) {
    bool inlined = false;
    out.scripts = parse_scripts(j["scripts"], catalog, origin, &inlined);
    // Scripts read from files travel inlined in the stored text: the package needs no other file.
    if (inlined) {
      try {
        out.source_json = j.dump(1);
      } catch (const json::exception& e) {
        throw std::invalid_argument(origin + ": $.scripts: a script file is not UTF-8 text: " + e.what());
      }
    }
  }
  return out;
}

SceneConfig load_scene_config(const std::string& path, const protocol::Catalog& catalog) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path + ": cannot open scene config");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_scene_config(ss.str(), catalog, path);
}

SceneConfig load_scene_config(const std::string& path) { return load_scene_config(path, *protocol::active_catalog()); }

}  // namespace meter::config
