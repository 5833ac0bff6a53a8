// The "scripts" part of the scene config: every input a catalog signal, every output a property
// with its target named, limits in range, the code Lua text that compiles. Scene names (nodes,
// materials, animations) are checked by the converter against the scene (resolve_config).
#include "scene_scripts_parser.hpp"

#include "config_json.hpp"
#include "meter/config/lua_syntax.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>


namespace meter::config {
using namespace meter::bridge;  // the vocabulary the parsers fill
namespace {

using nlohmann::json;

using config_json::Ctx;
using config_json::check_keys;
using config_json::number;
using config_json::string;

bool lua_identifier(const std::string& s) {
  static const std::set<std::string> reserved{"and",   "break", "do",  "else", "elseif", "end",   "false", "for",
                                              "function", "goto", "if", "in",   "local",  "nil",   "not",   "or",
                                              "repeat", "return", "then", "true", "until", "while"};
  if (s.empty() || s.size() > 64 || reserved.count(s)) return false;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char ch = s[i];
    const bool alpha = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || ch == '_';
    if (!alpha && !(i > 0 && ch >= '0' && ch <= '9')) return false;
  }
  return true;
}

struct PropertySpec {
  ScriptOutputKind kind;
  const char* target_key;  // "node", "material" or "animation"
};

const std::map<std::string, PropertySpec>& properties() {
  static const std::map<std::string, PropertySpec> p{
      {"time", {ScriptOutputKind::Animation, "animation"}},  {"visible", {ScriptOutputKind::Visible, "node"}},
      {"translation", {ScriptOutputKind::Translation, "node"}}, {"rotation", {ScriptOutputKind::Rotation, "node"}},
      {"morph", {ScriptOutputKind::Morph, "node"}},           {"color", {ScriptOutputKind::Color, "material"}},
      {"emissive", {ScriptOutputKind::Emissive, "material"}}, {"text", {ScriptOutputKind::Text, "node"}}};
  return p;
}

ScriptOutput parse_output(const Ctx& c, const std::string& name, const json& o, const std::string& path) {
  if (!lua_identifier(name)) c.fail(path, "an output name must be a Lua identifier (letters, digits, _)");
  if (!o.is_object()) c.fail(path, "expected an object {\"property\": ..., \"node\"|\"material\"|\"animation\": ...}");
  if (!o.contains("property")) c.fail(path + ".property", "missing (time, visible, translation, rotation, morph, color, emissive or text)");
  const std::string& prop = string(c, o["property"], path + ".property");
  const auto it = properties().find(prop);
  if (it == properties().end()) {
    c.fail(path + ".property", "unknown property \"" + prop + "\" (expected time, visible, translation, rotation, morph, color, emissive or text)");
  }
  ScriptOutput out;
  out.name = name;
  out.kind = it->second.kind;
  std::set<std::string> keys{"property", it->second.target_key, "failsafe", "comment"};
  if (!o.contains(it->second.target_key)) c.fail(path + "." + it->second.target_key, "missing (required for property \"" + prop + "\")");
  out.target = string(c, o[it->second.target_key], path + "." + it->second.target_key);
  if (out.kind == ScriptOutputKind::Morph) {
    keys.insert("target");
    if (o.contains("target")) {
      const double t = number(c, o["target"], path + ".target");
      if (t < 0 || t > 255 || t != std::floor(t)) c.fail(path + ".target", "expected a morph target index 0..255");
      out.morph_target = static_cast<int>(t);
    }
  }
  if (out.kind == ScriptOutputKind::Text) {
    keys.insert({"size_px", "color", "align"});
    if (o.contains("size_px")) {
      out.size_px = number(c, o["size_px"], path + ".size_px");
      if (out.size_px < 4 || out.size_px > 512) c.fail(path + ".size_px", "expected 4..512 pixels");
    }
    if (o.contains("color")) {
      out.color = config_json::colour(c, o["color"], path + ".color");
    }
    if (o.contains("align")) {
      out.align = config_json::parse_align(c, o["align"], path + ".align");
    }
  }
  check_keys(c, o, path, keys);
  if (o.contains("failsafe")) {
    const json& f = o["failsafe"];
    const std::string fp = path + ".failsafe";
    const int n = value_components(out.kind);
    if (out.kind == ScriptOutputKind::Visible) {
      if (!f.is_boolean()) c.fail(fp, "expected true or false (the lamp's look while the script is failed)");
      out.failsafe_visible = f.get<bool>();
    } else if (out.kind == ScriptOutputKind::Text) {
      out.failsafe_text = string(c, f, fp);
    } else if (n == 1) {
      out.failsafe_numbers = std::vector<double>{number(c, f, fp)};
    } else if (out.kind == ScriptOutputKind::Color) {
      const auto v = config_json::colour(c, f, fp);  // rgb or rgba (alpha 1), components >= 0
      out.failsafe_numbers = std::vector<double>(v.begin(), v.end());
    } else {
      const auto v = config_json::numbers<3>(c, f, fp);
      out.failsafe_numbers = std::vector<double>(v.begin(), v.end());
    }
  }
  return out;
}

std::string read_script_file(const Ctx& c, const std::string& file, const std::string& path) {
  const std::filesystem::path full = std::filesystem::path(c.origin).parent_path() / file;
  std::ifstream in(full, std::ios::binary);
  if (!in) c.fail(path, "cannot open script file " + full.string());
  std::stringstream ss;
  ss << in.rdbuf();
  std::string code = ss.str();
  if (code.size() > (1u << 20)) c.fail(path, full.string() + ": a script is at most 1 MiB");
  return code;
}

ScriptLimits parse_limits(const Ctx& c, const json& l, const std::string& path) {
  if (!l.is_object()) c.fail(path, "expected an object");
  check_keys(c, l, path, {"instructions", "memory_kb", "run_alloc_kb"});
  ScriptLimits out;
  auto bounded = [&](const char* key, double lo, double hi) {
    const double v = number(c, l[key], path + "." + key);
    if (v < lo || v > hi || v != std::floor(v)) {
      c.fail(path + "." + key, "expected an integer " + std::to_string(static_cast<long long>(lo)) + ".." + std::to_string(static_cast<long long>(hi)));
    }
    return v;
  };
  if (l.contains("instructions")) out.instructions = static_cast<long long>(bounded("instructions", 1000, 1e7));
  if (l.contains("memory_kb")) out.memory_bytes = static_cast<std::size_t>(bounded("memory_kb", 64, 65536)) * 1024;
  if (l.contains("run_alloc_kb")) out.run_alloc_bytes = static_cast<std::size_t>(bounded("run_alloc_kb", 64, 262144)) * 1024;
  return out;
}

// The property an output sets, as a key: two outputs (in one or two scripts) may not set one.
std::string property_key(const ScriptOutput& o) {
  std::string k = std::string(to_string(o.kind)) + " of " + o.target;
  if (o.kind == ScriptOutputKind::Morph) k += " target " + std::to_string(o.morph_target);
  return k;
}

}  // namespace

std::vector<Script> parse_scripts(json& scripts, const protocol::Catalog& catalog, const std::string& origin, bool* inlined) {
  const Ctx c{origin, catalog};
  if (inlined) *inlined = false;
  if (!scripts.is_array()) c.fail("$.scripts", "expected an array of scripts");
  std::vector<Script> out;
  std::map<std::string, std::string> written;  // property key -> "script.output"
  for (std::size_t i = 0; i < scripts.size(); ++i) {
    json& s = scripts[i];
    const std::string path = "$.scripts[" + std::to_string(i) + "]";
    if (!s.is_object()) c.fail(path, "expected an object");
    check_keys(c, s, path, {"name", "code", "file", "inlined_from", "inputs", "outputs", "limits", "comment"});
    Script sc;
    if (!s.contains("name")) c.fail(path + ".name", "missing (the script's name in messages and stats)");
    sc.name = string(c, s["name"], path + ".name");
    if (!lua_identifier(sc.name)) c.fail(path + ".name", "a script name must be a Lua identifier (letters, digits, _)");
    for (const auto& prior : out)
      if (prior.name == sc.name) c.fail(path + ".name", "a second script named \"" + sc.name + "\"");
    const std::string where = path + " (" + sc.name + ")";
    if (s.contains("code") == s.contains("file")) c.fail(where, "expected exactly one of \"code\" (Lua text) or \"file\" (a .lua file next to the config)");
    if (s.contains("file")) {
      sc.file = string(c, s["file"], path + ".file");
      sc.code = read_script_file(c, sc.file, path + ".file");
    } else {
      sc.code = string(c, s["code"], path + ".code");
      if (s.contains("inlined_from")) sc.file = string(c, s["inlined_from"], path + ".inlined_from");
    }
    const std::string code_path = s.contains("file") ? path + ".file (" + sc.file + ")" : path + ".code";
    if (const std::string why = lua_syntax_error(sc.code, sc.name); !why.empty()) c.fail(code_path, why);
    if (!s.contains("inputs") || !s["inputs"].is_object() || s["inputs"].empty()) {
      c.fail(path + ".inputs", "expected an object {\"name\": \"Catalog.Signal\", ...} with at least one input (a script runs when an input changes)");
    }
    for (auto it = s["inputs"].begin(); it != s["inputs"].end(); ++it) {
      const std::string ip = path + ".inputs." + it.key();
      if (!lua_identifier(it.key())) c.fail(ip, "an input name must be a Lua identifier (letters, digits, _)");
      ScriptInput in{it.key(), "", -1};
      in.signal_id = config_json::catalog_signal(c, it.value(), ip, in.signal);
      sc.inputs.push_back(std::move(in));
    }
    if (!s.contains("outputs") || !s["outputs"].is_object() || s["outputs"].empty()) {
      c.fail(path + ".outputs", "expected an object {\"name\": {\"property\": ..., ...}, ...} with at least one output");
    }
    for (auto it = s["outputs"].begin(); it != s["outputs"].end(); ++it) {
      ScriptOutput o = parse_output(c, it.key(), it.value(), path + ".outputs." + it.key());
      const std::string key = property_key(o);
      const std::string who = sc.name + "." + o.name;
      if (const auto w = written.find(key); w != written.end()) {
        c.fail(path + ".outputs." + o.name, "the " + key + " is already set by " + w->second + " (one writer per property)");
      }
      written.emplace(key, who);
      sc.outputs.push_back(std::move(o));
    }
    if (s.contains("limits")) sc.limits = parse_limits(c, s["limits"], path + ".limits");
    if (s.contains("file")) {
      s.erase("file");
      s["code"] = sc.code;
      s["inlined_from"] = sc.file;
      if (inlined) *inlined = true;
    }
    out.push_back(std::move(sc));
  }
  return out;
}

}  // namespace meter::config
