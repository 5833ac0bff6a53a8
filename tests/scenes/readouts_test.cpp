// The shipped scenes' text readouts against the catalog's enums, through the engine's own path:
// every scene config under scenes/ parsed by meter::config (as the converter and the package
// reader parse it) and each readout's text made by engine::binding_text (as BindingEvaluator makes
// it; the imperial look by engine::imperial_binding). Pure: no GL, no scene geometry.
// - the cluster's gear readout shows every CurrentGear value the catalog allows as VSS names it:
//   R, N, the forward gear's number, P, D;
// - no readout of any shipped scene shows a named enum value (a code the catalog's description
//   gives a name, e.g. 127=Drive) as its bare number;
// - every enum signal of the catalog is listed below, with its named values, so a new enum or a
//   renamed code fails here until it is described.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "meter/config/scene_config_parser.hpp"
#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/evaluation/scene_features.hpp"
#include "meter/protocol/catalog.hpp"

namespace fs = std::filesystem;
using meter::bridge::Binding;
using meter::bridge::BindingKind;
using meter::protocol::SignalKind;

namespace {

// The codes of one enum signal that carry a name: lo..hi, and the words of the catalog's
// description that name them (checked to be there, so this table cannot drift from the catalog).
struct NamedCodes {
  long long lo, hi;
  std::string description_words;
};

// Every enum signal of the shipped catalog. Codes not listed are numbers that mean themselves
// (a forward gear, a page index) and may be shown as such.
const std::map<std::string, std::vector<NamedCodes>>& named_enum_codes() {
  static const std::map<std::string, std::vector<NamedCodes>> table{
      {"Vehicle.Powertrain.Transmission.CurrentGear",
       {{-128, -1, "-1/-2/..=Reverse"}, {0, 0, "0=Neutral"}, {126, 126, "126=Park"}, {127, 127, "127=Drive"}}},
      {"Vehicle.LowVoltageSystemState",
       {{0, 0, "0 UNDEFINED"}, {1, 1, "1 LOCK"}, {2, 2, "2 OFF"}, {3, 3, "3 ACC"}, {4, 4, "4 ON"}, {5, 5, "5 START"}}},
      {"Vehicle.Cabin.Infotainment.HMI.DistanceUnit", {{0, 0, "0 KILOMETERS"}, {1, 1, "1 MILES"}}},
      {"Vehicle.Cabin.Infotainment.HMI.TemperatureUnit", {{0, 0, "0 C"}, {1, 1, "1 F"}}},
      {"Vehicle.Cabin.Infotainment.HMI.DayNightMode", {{0, 0, "0 DAY"}, {1, 1, "1 NIGHT"}}},
      {"Cluster.Page", {}},  // a page index: its number
  };
  return table;
}

bool named(const std::string& signal, long long code) {
  const auto it = named_enum_codes().find(signal);
  if (it == named_enum_codes().end()) return false;
  return std::any_of(it->second.begin(), it->second.end(), [&](const NamedCodes& n) { return code >= n.lo && code <= n.hi; });
}

// The shipped catalog's JSON leaf of a dotted name (descriptions and `allowed` are not in SignalInfo).
const nlohmann::json* catalog_leaf(const nlohmann::json& root, const std::string& name) {
  const nlohmann::json* node = &root;
  std::size_t start = 0;
  for (;;) {
    const auto dot = name.find('.', start);
    const std::string part = name.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (node != &root && !node->contains("children")) return nullptr;
    const nlohmann::json& children = node == &root ? root : node->at("children");
    if (!children.is_object() || !children.contains(part)) return nullptr;
    node = &children.at(part);
    if (dot == std::string::npos) return node;
    start = dot + 1;
  }
}

const nlohmann::json& catalog_json() {
  static const nlohmann::json j = nlohmann::json::parse(meter::protocol::default_catalog()->text());
  return j;
}

// Every code the catalog lets the signal take: its `allowed` list, else the integers min..max.
std::vector<long long> enum_domain(const meter::protocol::SignalInfo& s) {
  std::vector<long long> codes;
  const nlohmann::json* leaf = catalog_leaf(catalog_json(), s.name);
  if (leaf && leaf->contains("allowed")) {
    for (const auto& v : (*leaf)["allowed"])
      if (v.is_number()) codes.push_back(v.get<long long>());
    return codes;
  }
  for (auto c = static_cast<long long>(std::ceil(s.min)); c <= static_cast<long long>(std::floor(s.max)); ++c) codes.push_back(c);
  return codes;
}

struct ShippedConfig {
  std::string path;
  meter::bridge::SceneConfig config;
};

// Every scene config under scenes/ (name.scene.json, or scene.json in a feature's folder), so a
// scene added later is checked without touching this test.
std::vector<ShippedConfig> shipped_configs() {
  std::vector<ShippedConfig> out;
  for (const auto& e : fs::recursive_directory_iterator(fs::path(METER_SOURCE_DIR) / "scenes")) {
    const std::string file = e.path().filename().string();
    if (!e.is_regular_file() || !(file == "scene.json" || file.ends_with(".scene.json"))) continue;
    out.push_back({e.path().string(), meter::config::load_scene_config(e.path().string(), *meter::protocol::default_catalog())});
  }
  std::sort(out.begin(), out.end(), [](const ShippedConfig& a, const ShippedConfig& b) { return a.path < b.path; });
  return out;
}

// The texts a readout shows for a value: the metric look, and the imperial one when it has a quantity.
std::vector<std::string> readout_texts(const Binding& b, double value) {
  std::vector<std::string> t{meter::engine::binding_text(b, value)};
  if (b.units.quantity != meter::bridge::Quantity::None) t.push_back(meter::engine::binding_text(meter::engine::imperial_binding(b), value));
  return t;
}

}  // namespace

TEST(Readouts, EveryCatalogEnumIsDescribedHere) {
  const auto& table = named_enum_codes();
  for (const auto& s : meter::protocol::default_catalog()->signals()) {
    if (s.kind != SignalKind::Enum) continue;
    const auto it = table.find(s.name);
    ASSERT_NE(it, table.end()) << s.name << " is an enum of the catalog: list its named codes in named_enum_codes()";
    const nlohmann::json* leaf = catalog_leaf(catalog_json(), s.name);
    ASSERT_NE(leaf, nullptr) << s.name;
    const std::string description = leaf->value("description", "");
    for (const NamedCodes& n : it->second)
      EXPECT_NE(description.find(n.description_words), std::string::npos)
          << s.name << ": the catalog's description no longer says '" << n.description_words << "': " << description;
  }
  for (const auto& [name, codes] : table) {
    const auto* s = meter::protocol::default_catalog()->find(name);
    ASSERT_NE(s, nullptr) << name << " is listed here but not in the catalog";
    EXPECT_EQ(s->kind, SignalKind::Enum) << name;
  }
}

// An automatic's Drive (127) showed "127": the gear readout mapped only -1, 0 and 126.
TEST(Readouts, ClusterGearShowsEveryCurrentGearTheCatalogAllows) {
  const auto* gear = meter::protocol::default_catalog()->find("Vehicle.Powertrain.Transmission.CurrentGear");
  ASSERT_NE(gear, nullptr);
  const auto cluster = meter::config::load_scene_config(METER_SOURCE_DIR "/scenes/cluster/cluster.scene.json",
                                                        *meter::protocol::default_catalog());
  const auto b = std::find_if(cluster.bindings.begin(), cluster.bindings.end(),
                              [&](const Binding& x) { return x.kind == BindingKind::Text && x.signal == gear->name; });
  ASSERT_NE(b, cluster.bindings.end()) << "the cluster has no gear readout";
  const std::vector<long long> codes = enum_domain(*gear);
  ASSERT_EQ(codes.front(), -1);
  ASSERT_EQ(codes.back(), 127);
  for (long long c : codes) {
    const std::string want = c < 0 ? "R" : c == 0 ? "N" : c == 126 ? "P" : c == 127 ? "D" : std::to_string(c);
    EXPECT_EQ(meter::engine::binding_text(*b, static_cast<double>(c)), want) << "CurrentGear " << c;
  }
}

TEST(Readouts, NoShippedReadoutShowsANamedEnumCodeAsItsNumber) {
  const auto configs = shipped_configs();
  ASSERT_GE(configs.size(), 15u) << "the scenes/ tree: minimal-gauge, cluster and 13 feature scenes";
  int enum_readouts = 0;
  for (const ShippedConfig& sc : configs) {
    for (const Binding& b : sc.config.bindings) {
      const auto* s = meter::protocol::default_catalog()->find(b.signal);
      if (b.kind != BindingKind::Text || !s || s->kind != SignalKind::Enum) continue;
      ++enum_readouts;
      for (long long c : enum_domain(*s)) {
        if (!named(s->name, c)) continue;
        for (const std::string& text : readout_texts(b, static_cast<double>(c))) {
          const bool numeral = !text.empty() && std::all_of(text.begin() + (text[0] == '-' ? 1 : 0), text.end(),
                                                            [](char ch) { return ch >= '0' && ch <= '9'; });
          EXPECT_FALSE(text.empty() || numeral || text == "---")
              << sc.path << ": readout " << b.node << " of " << s->name << " shows code " << c << " as '" << text
              << "'; the catalog names it: add it to the binding's map";
        }
      }
    }
  }
  EXPECT_GE(enum_readouts, 1) << "the cluster's gear readout is an enum readout";
}
