// The JSON reading helpers of the scene config parsers: typed values with errors naming the file,
// the JSON path and what was expected. Internal to meter_scene_config.
#pragma once

#include <array>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "meter/bridge/scene_config.hpp"
#include "meter/protocol/catalog.hpp"

namespace meter::config::config_json {

using nlohmann::json;

struct Ctx {
  std::string origin;
  const protocol::Catalog& catalog;  // binding signal names are checked against it
  [[noreturn]] void fail(const std::string& path, const std::string& what) const {
    throw std::invalid_argument(origin + ": " + path + ": " + what);
  }
};

inline double number(const Ctx& c, const json& j, const std::string& path) {
  if (!j.is_number()) c.fail(path, "expected a number, got " + std::string(j.type_name()));
  double v = j.get<double>();
  if (!std::isfinite(v)) c.fail(path, "expected a finite number");
  return v;
}

inline std::string string(const Ctx& c, const json& j, const std::string& path) {
  if (!j.is_string()) c.fail(path, "expected a string, got " + std::string(j.type_name()));
  return j.get<std::string>();
}

inline bool boolean(const Ctx& c, const json& j, const std::string& path) {
  if (!j.is_boolean()) c.fail(path, "expected true or false, got " + std::string(j.type_name()));
  return j.get<bool>();
}

template <std::size_t N>
inline std::array<double, N> numbers(const Ctx& c, const json& j, const std::string& path,
                              std::size_t min_count = N) {
  if (!j.is_array() || j.size() < min_count || j.size() > N) {
    c.fail(path, "expected an array of " +
                     (min_count == N ? std::to_string(N) : std::to_string(min_count) + ".." +
                                                               std::to_string(N)) +
                     " numbers");
  }
  std::array<double, N> out{};
  if (N == 4) out[N - 1] = 1.0;  // colours: alpha defaults to 1 when only rgb is given
  for (std::size_t i = 0; i < j.size(); ++i) out[i] = number(c, j[i], path + "[" + std::to_string(i) + "]");
  return out;
}

inline void check_keys(const Ctx& c, const json& obj, const std::string& path,
                const std::set<std::string>& allowed) {
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    if (!allowed.count(it.key())) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      c.fail(path + "." + it.key(), "unknown key (expected one of: " + list + ")");
    }
  }
}

inline TextAlign parse_align(const Ctx& c, const json& j, const std::string& path) {
  std::string s = string(c, j, path);
  if (s == "left") return TextAlign::Left;
  if (s == "center" || s == "centre") return TextAlign::Center;
  if (s == "right") return TextAlign::Right;
  c.fail(path, "expected \"left\", \"center\" or \"right\", got \"" + s + "\"");
}

inline std::array<double, 4> colour(const Ctx& c, const json& j, const std::string& path) {
  auto v = numbers<4>(c, j, path, 3);
  for (std::size_t i = 0; i < 4; ++i) {
    if (v[i] < 0.0) c.fail(path + "[" + std::to_string(i) + "]", "colour components must be >= 0");
  }
  return v;
}

inline std::array<double, 2> range(const Ctx& c, const json& j, const std::string& path) {
  auto r = numbers<2>(c, j, path);
  if (r[0] == r[1]) c.fail(path, "the two ends of the range must differ");
  return r;
}

// A catalog signal name at `path`: its id, or an error naming the catalog.
inline int catalog_signal(const Ctx& c, const json& j, const std::string& path, std::string& name) {
  name = string(c, j, path);
  const auto* info = c.catalog.find(name);
  if (!info) c.fail(path, "\"" + name + "\" is not in the signal catalog " + c.catalog.source());
  return info->id;
}

// An array of names (nodes, animations) at `path`.
inline std::vector<std::string> strings(const Ctx& c, const json& j, const std::string& path) {
  if (!j.is_array()) c.fail(path, "expected an array of names");
  std::vector<std::string> out;
  for (std::size_t i = 0; i < j.size(); ++i) out.push_back(string(c, j[i], path + "[" + std::to_string(i) + "]"));
  return out;
}

}  // namespace meter::config::config_json
