// parse_catalog(): a COVESA VSS JSON tree (as `vspec export json` writes it) -> Catalog.
//
// Branches: {"type": "branch", "description": ..., "children": {NAME: node, ...}}.
// Leaves: {"type": "sensor"|"actuator"|"attribute", "datatype": ..., "unit"?, "min"?, "max"?,
// "allowed"?, "description"?, "meter_id": N, "meter_kind"?: "gauge"|"enum"|"counter"|"telltale"|"text"}.
// meter_id and meter_kind are this project's extended attributes (vss-tools passes extended
// attributes through to the JSON export unchanged); everything else VSS writes (uuid, comment,
// deprecation, default, ...) is accepted and ignored. The full rules: docs/catalog.md.
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <nlohmann/json.hpp>

#include "meter/protocol/catalog.hpp"

namespace meter::protocol {
namespace {

using nlohmann::json;

constexpr std::size_t kMaxCatalogBytes = 1 << 20;  // fits the CATALOG transfer (docs/protocol.md)
constexpr int kMaxDepth = 16;                      // VSS trees are 3-6 deep

struct Failure {
  std::string message;
};

// One JSON pointer (RFC 6901) step: "~" and "/" in a key are escaped.
std::string step(const std::string& key) {
  std::string out = "/";
  for (char ch : key) {
    if (ch == '~') {
      out += "~0";
    } else if (ch == '/') {
      out += "~1";
    } else {
      out += ch;
    }
  }
  return out;
}

struct DatatypeInfo {
  std::string_view name;
  double lo, hi;  // representable range (integers); NaN = unbounded
  bool integer;
};

constexpr double kNoBound = std::numeric_limits<double>::quiet_NaN();
constexpr DatatypeInfo kDatatypes[] = {
    {"uint8", 0, 255, true},           {"int8", -128, 127, true},
    {"uint16", 0, 65535, true},        {"int16", -32768, 32767, true},
    {"uint32", 0, 4294967295.0, true}, {"int32", -2147483648.0, 2147483647.0, true},
    {"uint64", 0, 18446744073709551615.0, true},
    {"int64", -9223372036854775808.0, 9223372036854775807.0, true},
    {"float", kNoBound, kNoBound, false}, {"double", kNoBound, kNoBound, false},
    {"boolean", 0, 1, true},           {"string", kNoBound, kNoBound, false},
};

struct Walker {
  std::string file;
  std::vector<SignalInfo> signals;
  std::map<SignalId, std::string> id_owner;  // meter_id -> VSS name, to name both on a clash

  [[noreturn]] void fail(const std::string& pointer, const std::string& what) const {
    throw Failure{file + ": " + (pointer.empty() ? "/" : pointer) + ": " + what};
  }

  static std::string type_name(const json& j) { return j.type_name(); }
  // A value for a message: scalars as written, containers by type only (never a recursive dump
  // of a hostile, deeply nested value).
  static std::string brief(const json& j) {
    if (j.is_structured()) return j.empty() ? (j.is_array() ? "[]" : "{}") : "an " + type_name(j);
    return j.dump();
  }

  const std::string& string_field(const json& node, const std::string& pointer, const char* key, bool required) const {
    static const std::string kEmpty;
    auto it = node.find(key);
    if (it == node.end()) {
      if (required) fail(pointer, std::string("expected a \"") + key + "\" field");
      return kEmpty;
    }
    if (!it->is_string()) fail(pointer + "/" + key, "expected a string, got " + type_name(*it));
    return it->get_ref<const std::string&>();
  }

  std::optional<double> number_field(const json& node, const std::string& pointer, const char* key) const {
    auto it = node.find(key);
    if (it == node.end()) return std::nullopt;
    if (!it->is_number()) fail(pointer + "/" + key, "expected a number, got " + type_name(*it));
    const double v = it->get<double>();
    if (!std::isfinite(v)) fail(pointer + "/" + key, "expected a finite number");
    return v;
  }

  void node(const json& j, const std::string& name, const std::string& pointer, int depth) {
    if (depth > kMaxDepth) fail(pointer, "expected at most " + std::to_string(kMaxDepth) + " levels of branches");
    if (!j.is_object()) fail(pointer, "expected a VSS node (an object), got " + type_name(j));
    const std::string& type = string_field(j, pointer, "type", true);
    string_field(j, pointer, "description", false);
    if (type == "branch") {
      auto it = j.find("children");
      if (it == j.end()) fail(pointer, "expected a \"children\" object in a branch");
      if (!it->is_object()) fail(pointer + "/children", "expected an object, got " + type_name(*it));
      for (const auto& [key, child] : it->items()) {
        if (key.empty() || key.find('.') != std::string::npos) {
          fail(pointer + "/children" + step(key), "expected a node name without '.' (the path is built from the tree)");
        }
        node(child, name + "." + key, pointer + "/children" + step(key), depth + 1);
      }
      return;
    }
    if (type != "sensor" && type != "actuator" && type != "attribute") {
      fail(pointer + "/type", "expected \"branch\", \"sensor\", \"actuator\" or \"attribute\", got \"" + type + "\"");
    }
    leaf(j, name, pointer);
  }

  void leaf(const json& j, const std::string& name, const std::string& pointer) {
    SignalInfo s;
    s.name = name;
    const std::string& datatype = string_field(j, pointer, "datatype", true);
    const DatatypeInfo* dt = nullptr;
    for (const auto& d : kDatatypes) {
      if (d.name == datatype) dt = &d;
    }
    if (dt == nullptr) {
      fail(pointer + "/datatype",
           "expected a scalar VSS datatype (uint8..int64, float, double, boolean, string), got \"" + datatype + "\"");
    }
    s.unit = string_field(j, pointer, "unit", false);

    auto id = j.find("meter_id");
    if (id == j.end()) fail(pointer, "expected a \"meter_id\" field (the signal's wire id, 1..65535)");
    if (!id->is_number_integer() || id->get<long long>() < 1 || id->get<long long>() > 65535) {
      fail(pointer + "/meter_id", "expected an integer 1..65535, got " + brief(*id));
    }
    s.id = static_cast<SignalId>(id->get<long long>());
    if (auto [it, fresh] = id_owner.emplace(s.id, name); !fresh) {
      fail(pointer + "/meter_id", "id " + std::to_string(s.id) + " is already used by " + it->second);
    }

    const std::string& kind_text = string_field(j, pointer, "meter_kind", false);
    if (kind_text.empty()) {
      s.kind = datatype == "boolean" ? SignalKind::Telltale : datatype == "string" ? SignalKind::Text : SignalKind::Gauge;
    } else if (auto k = kind_from_string(kind_text)) {
      s.kind = *k;
    } else {
      fail(pointer + "/meter_kind", "expected \"gauge\", \"enum\", \"counter\", \"telltale\" or \"text\", got \"" +
                                        kind_text + "\"");
    }
    if ((s.kind == SignalKind::Text) != (datatype == "string")) {
      fail(pointer + "/meter_kind", "expected \"text\" exactly for datatype string (got kind \"" +
                                        std::string(to_string(s.kind)) + "\", datatype \"" + datatype + "\")");
    }

    const auto min = number_field(j, pointer, "min");
    const auto max = number_field(j, pointer, "max");
    if (datatype == "boolean" || datatype == "string") {
      s.min = min.value_or(0.0);
      s.max = max.value_or(datatype == "boolean" ? 1.0 : 0.0);
    } else {
      if (!min) fail(pointer, "expected a \"min\" field (the lowest value the view is designed for)");
      if (!max) fail(pointer, "expected a \"max\" field (the highest value the view is designed for)");
      s.min = *min;
      s.max = *max;
    }
    if (s.min > s.max) fail(pointer + "/max", "expected max >= min (" + json(s.min).dump() + ")");
    if (s.kind == SignalKind::Telltale && (s.min != 0.0 || s.max != 1.0)) {
      fail(pointer, "expected the range 0..1 for a telltale (a lamp is off or on)");
    }
    if (dt->integer && (s.min < dt->lo || s.max > dt->hi)) {
      fail(pointer, "expected min and max within the " + datatype + " range " + json(dt->lo).dump() + ".." +
                        json(dt->hi).dump());
    }

    if (auto allowed = j.find("allowed"); allowed != j.end()) {
      if (!allowed->is_array() || allowed->empty()) {
        fail(pointer + "/allowed", "expected a non-empty array, got " + brief(*allowed));
      }
      for (std::size_t i = 0; i < allowed->size(); ++i) {
        const json& a = (*allowed)[i];
        const std::string at = pointer + "/allowed/" + std::to_string(i);
        if (a.is_number()) {
          const double v = a.get<double>();
          if (!(v >= s.min && v <= s.max)) fail(at, "expected a value within min..max, got " + a.dump());
        } else if (!a.is_string()) {
          fail(at, "expected a number or a string, got " + type_name(a));
        }
      }
    }
    signals.push_back(std::move(s));
  }
};

// JSON leaves a duplicate key's meaning open and the parser keeps the last one, which would drop a
// signal without a word: the parse callback tracks where it is and records the first duplicate.
class DuplicateKeyFinder {
 public:
  bool operator()(int /*depth*/, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start: stack_.push_back({false, {}, {}, 0}); break;
      case json::parse_event_t::array_start: stack_.push_back({true, {}, {}, 0}); break;
      case json::parse_event_t::key: {
        Level& top = stack_.back();
        top.key = parsed.get<std::string>();
        if (!top.keys.insert(top.key).second && !first_) first_ = pointer();
        break;
      }
      case json::parse_event_t::value: element_done(); break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        stack_.pop_back();
        element_done();
        break;
    }
    return true;
  }
  const std::optional<std::string>& first() const { return first_; }

 private:
  struct Level {
    bool array;
    std::set<std::string> keys;
    std::string key;    // object: the key being read
    std::size_t index;  // array: elements completed so far = the index of the one being read
  };
  void element_done() {
    if (!stack_.empty() && stack_.back().array) ++stack_.back().index;
  }
  std::string pointer() const {
    std::string out;
    for (const auto& l : stack_) out += l.array ? "/" + std::to_string(l.index) : step(l.key);
    return out;
  }
  std::vector<Level> stack_;
  std::optional<std::string> first_;
};

std::string line_and_column(std::string_view text, std::size_t byte) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return std::to_string(line) + ":" + std::to_string(column);
}

}  // namespace

CatalogParseResult parse_catalog(std::string_view text, std::string_view file_name) {
  const std::string file(file_name);
  if (text.size() > kMaxCatalogBytes) {
    return {nullptr, file + ": expected at most " + std::to_string(kMaxCatalogBytes) + " bytes, got " +
                         std::to_string(text.size())};
  }
  json root;
  // Shared: the parser copies its callback, the finder's state must outlive the copy.
  auto duplicates = std::make_shared<DuplicateKeyFinder>();
  try {
    root = json::parse(text.begin(), text.end(),
                       [duplicates](int depth, json::parse_event_t event, json& parsed) {
                         return (*duplicates)(depth, event, parsed);
                       });
  } catch (const json::parse_error& e) {
    // e.byte is 1-based: the byte at which the parser gave up.
    const std::string what = e.what();
    const auto colon = what.find("parse error");
    return {nullptr, file + ":" + line_and_column(text, e.byte > 0 ? e.byte - 1 : 0) +
                         ": not valid JSON: " + (colon == std::string::npos ? what : what.substr(colon))};
  } catch (const json::exception& e) {
    // A number too large for a double (out_of_range) is the other JSON error: it has no byte
    // offset of its own, but the message quotes the number, which is found in the text.
    const std::string what = e.what();
    const auto quote = what.find('\'');
    const auto end = quote == std::string::npos ? quote : what.find('\'', quote + 1);
    const auto at = end == std::string::npos ? std::string::npos : text.find(what.substr(quote + 1, end - quote - 1));
    const auto message = what.find("number overflow");
    return {nullptr, file + (at == std::string::npos ? "" : ":" + line_and_column(text, at)) + ": not valid JSON: " +
                         (message == std::string::npos ? what : what.substr(message))};
  }
  if (const auto& at = duplicates->first()) {
    return {nullptr, file + ": " + *at + ": the key appears twice (a JSON object's keys must be unique)"};
  }
  try {
    Walker w{file, {}, {}};
    if (!root.is_object() || root.empty()) {
      w.fail("", "expected an object of root branches (\"Vehicle\": {...}), got " + (root.is_object() ? std::string("{}") : Walker::type_name(root)));
    }
    for (const auto& [key, child] : root.items()) {
      if (key.empty() || key.find('.') != std::string::npos) w.fail(step(key), "expected a root name without '.'");
      w.node(child, key, step(key), 1);
    }
    if (w.signals.empty()) w.fail("", "expected at least one sensor, actuator or attribute");
    return {std::make_shared<const Catalog>(std::move(w.signals), file, std::string(text)), {}};
  } catch (const Failure& f) {
    return {nullptr, f.message};
  } catch (const std::exception& e) {  // a json type error the checks above missed, or bad_alloc
    return {nullptr, file + ": " + e.what()};
  }
}

}  // namespace meter::protocol
