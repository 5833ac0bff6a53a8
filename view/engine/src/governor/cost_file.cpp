// The meter-costs/1 file: parse and write (cost_file.hpp).
#include "meter/engine/governor/cost_file.hpp"

#include <cmath>
#include <set>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "governor/cost_limits.hpp"

namespace meter::engine::governor {
namespace {

using nlohmann::json;
using nlohmann::ordered_json;

struct Reader {
  const std::string& origin;

  [[noreturn]] void fail(const std::string& path, const std::string& what) const {
    throw std::invalid_argument(origin + ": " + path + ": " + what);
  }

  const json& member(const json& obj, const std::string& path, const char* key) const {
    const auto it = obj.find(key);
    if (it == obj.end()) fail(path + "." + key, "missing (a required key)");
    return *it;
  }

  void object(const json& j, const std::string& path, const std::set<std::string>& keys) const {
    if (!j.is_object()) fail(path, "expected an object, got " + std::string(j.type_name()));
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (keys.count(it.key())) continue;
      std::string list;
      for (const auto& k : keys) list += (list.empty() ? "" : ", ") + k;
      fail(path + "." + it.key(), "unknown key (expected one of: " + list + ")");
    }
  }

  const json& array(const json& obj, const std::string& path, const char* key) const {
    const json& j = member(obj, path, key);
    if (!j.is_array()) fail(path + "." + key, "expected an array, got " + std::string(j.type_name()));
    return j;
  }

  // A finite number in [lo, hi] (lo_open: lo itself excluded).
  double number(const json& obj, const std::string& path, const char* key, double lo, double hi,
                bool lo_open = false) const {
    const json& j = member(obj, path, key);
    const std::string at = path + "." + key;
    if (!j.is_number()) fail(at, "expected a number, got " + std::string(j.type_name()));
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(at, "expected a finite number");
    if (v < lo || v > hi || (lo_open && v == lo))
      fail(at, "expected a number in " + std::string(lo_open ? "(" : "[") + format(lo) + ", " + format(hi) +
                   "], got " + format(v));
    return v;
  }

  std::optional<double> psnr(const json& obj, const std::string& path) const {
    if (!obj.contains("psnr_db")) return std::nullopt;
    return number(obj, path, "psnr_db", 0.0, limits::kMaxPsnrDb, true);
  }

  std::string text(const json& obj, const std::string& path, const char* key) const {
    const json& j = member(obj, path, key);
    if (!j.is_string()) fail(path + "." + key, "expected a string, got " + std::string(j.type_name()));
    return j.get<std::string>();
  }

  // Whole numbers without a fraction ("1000", not "1000.0"), others as JSON writes them.
  static std::string format(double v) {
    if (std::abs(v) < 1e15 && v == std::floor(v)) return std::to_string(static_cast<long long>(v));
    return json(v).dump();
  }
};

LinearCost linear(const Reader& r, const json& j, const std::string& path) {
  return {r.number(j, path, "a_ms_per_pixel", 0.0, limits::kMaxMsPerPixel),
          r.number(j, path, "b_ms", -limits::kMaxFixedMs, limits::kMaxFixedMs)};
}

GlobalCost global(const Reader& r, const json& j, const std::string& path) {
  r.object(j, path, {"msaa", "scale", "pixel_factor", "fixed_ms", "psnr_db"});
  const json& msaa = r.member(j, path, "msaa");
  if (!msaa.is_number_integer() || msaa.get<long long>() < 1 || msaa.get<long long>() > limits::kMaxMsaa)
    r.fail(path + ".msaa", "expected an integer sample count in [1, " + std::to_string(limits::kMaxMsaa) + "]");
  GlobalCost g;
  g.level.msaa = msaa.get<int>();
  const double scale = r.number(j, path, "scale", 0.0, 1.0, true);
  g.level.scale = float(scale);
  // GlobalLevel holds a float: a scale that rounds to 0 would be a rung of no pixels.
  if (!(g.level.scale > 0))
    r.fail(path + ".scale", "expected a number in (0, 1] that a float can hold, got " + Reader::format(scale));
  g.pixel_factor = r.number(j, path, "pixel_factor", 0.0, limits::kMaxPixelFactor, true);
  g.fixed_ms = r.number(j, path, "fixed_ms", 0.0, limits::kMaxFixedMs);
  g.psnr_db = r.psnr(j, path);
  return g;
}

LevelCost level(const Reader& r, const json& j, const std::string& path) {
  r.object(j, path, {"shading", "lod", "a_ms_per_pixel", "b_ms", "psnr_db"});
  LevelCost l;
  const std::string name = r.text(j, path, "shading");
  const auto model = limits::shading_from_name(name);
  if (!model) r.fail(path + ".shading", "expected one of " + limits::shading_names() + ", got \"" + name + "\"");
  l.shading = *model;
  const json& lod = r.member(j, path, "lod");
  if (!lod.is_number_integer() || lod.get<long long>() < 0 || lod.get<long long>() > limits::kMaxLod)
    r.fail(path + ".lod", "expected an integer LOD index in [0, " + std::to_string(limits::kMaxLod) + "]");
  l.lod = lod.get<int>();
  l.cost = linear(r, j, path);
  l.psnr_db = r.psnr(j, path);
  return l;
}

UnitCostEntry unit(const Reader& r, const json& j, const std::string& path) {
  r.object(j, path, {"name", "levels"});
  UnitCostEntry u;
  u.name = r.text(j, path, "name");
  const json& levels = r.array(j, path, "levels");
  if (levels.empty()) r.fail(path + ".levels", "expected at least one level");
  std::set<std::pair<bridge::ShadingModel, int>> seen;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const std::string at = path + ".levels[" + std::to_string(i) + "]";
    u.levels.push_back(level(r, levels[i], at));
    if (!seen.insert({u.levels.back().shading, u.levels.back().lod}).second)
      r.fail(at, "duplicate level (expected each shading and lod once per unit)");
  }
  return u;
}

}  // namespace

CostFile parse_costs(const std::string& text, const std::string& origin) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::exception& e) {  // parse_error, and out_of_range for a number like 1e400
    throw std::invalid_argument(origin + ": invalid JSON: " + e.what());
  }
  const Reader r{origin};
  const std::string root = "$";
  r.object(doc, root, {"format", "backend", "package", "overhead", "globals", "units", "concatenation"});
  const std::string format = r.text(doc, root, "format");
  if (format != kCostFormat)
    r.fail(root + ".format", "expected \"" + std::string(kCostFormat) + "\", got \"" + format + "\"");
  CostFile f;
  if (doc.contains("backend")) f.backend = r.text(doc, root, "backend");
  if (doc.contains("package")) f.package = r.text(doc, root, "package");
  const json& overhead = r.member(doc, root, "overhead");
  r.object(overhead, root + ".overhead", {"a_ms_per_pixel", "b_ms"});
  f.overhead = linear(r, overhead, root + ".overhead");
  if (f.overhead.b_ms < 0) r.fail(root + ".overhead.b_ms", "expected a number >= 0");
  const json& globals = r.array(doc, root, "globals");
  if (globals.empty()) r.fail(root + ".globals", "expected at least one rung (the first is full quality)");
  for (std::size_t i = 0; i < globals.size(); ++i) {
    const std::string at = root + ".globals[" + std::to_string(i) + "]";
    f.globals.push_back(global(r, globals[i], at));
    for (std::size_t k = 0; k + 1 < f.globals.size(); ++k)
      if (f.globals[k].level == f.globals.back().level) r.fail(at, "duplicate rung (same msaa and scale as globals[" + std::to_string(k) + "])");
  }
  const json& units = r.array(doc, root, "units");
  for (std::size_t i = 0; i < units.size(); ++i) f.units.push_back(unit(r, units[i], root + ".units[" + std::to_string(i) + "]"));
  if (doc.contains("concatenation")) {
    const json& c = r.member(doc, root, "concatenation");
    const std::string at = root + ".concatenation";
    r.object(c, at, {"draw_ms", "vertex_ms", "transform_ms"});
    f.concatenation = ConcatenationCosts{r.number(c, at, "draw_ms", 0.0, limits::kMaxFixedMs),
                                         r.number(c, at, "vertex_ms", 0.0, limits::kMaxFixedMs),
                                         r.number(c, at, "transform_ms", 0.0, limits::kMaxFixedMs)};
  }
  return f;
}

std::string write_costs(const CostFile& file) {
  auto linear_json = [](ordered_json& j, const LinearCost& c) {
    j["a_ms_per_pixel"] = c.a_ms_per_pixel;
    j["b_ms"] = c.b_ms;
  };
  ordered_json doc = ordered_json::object();
  doc["format"] = kCostFormat;
  if (!file.backend.empty()) doc["backend"] = file.backend;
  if (!file.package.empty()) doc["package"] = file.package;
  linear_json(doc["overhead"], file.overhead);
  doc["globals"] = ordered_json::array();
  for (const GlobalCost& g : file.globals) {
    ordered_json j = {{"msaa", g.level.msaa}, {"scale", g.level.scale}, {"pixel_factor", g.pixel_factor}, {"fixed_ms", g.fixed_ms}};
    if (g.psnr_db) j["psnr_db"] = *g.psnr_db;
    doc["globals"].push_back(j);
  }
  doc["units"] = ordered_json::array();
  for (const UnitCostEntry& u : file.units) {
    ordered_json levels = ordered_json::array();
    for (const LevelCost& l : u.levels) {
      ordered_json j = {{"shading", bridge::to_string(l.shading)}, {"lod", l.lod}};
      linear_json(j, l.cost);
      if (l.psnr_db) j["psnr_db"] = *l.psnr_db;
      levels.push_back(j);
    }
    doc["units"].push_back({{"name", u.name}, {"levels", levels}});
  }
  if (file.concatenation)
    doc["concatenation"] = {{"draw_ms", file.concatenation->draw_ms},
                            {"vertex_ms", file.concatenation->vertex_ms},
                            {"transform_ms", file.concatenation->transform_ms}};
  return doc.dump(2) + "\n";
}

}  // namespace meter::engine::governor
