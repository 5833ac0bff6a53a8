// Value names of a mapping resolved against the DBC's VAL_ tables.
#include "meter/controller/mapping/value_names.hpp"

#include <cmath>

#include "meter/controller/mapping/sources.hpp"

namespace meter::controller {
namespace {

std::string known_names(const DbcSignal& s) {
  if (s.choices.empty()) return "it has no VAL_ table";
  std::string t = "its VAL_ names are";
  for (const auto& [raw, name] : s.choices) t += " " + std::to_string(raw) + " \"" + name + "\"";
  return t;
}

// The section's value for one raw value of a DBC signal: the signal's scaling, then the section's.
double section_value(const OutputMapping& o, const DbcSignal& s, std::int64_t raw) {
  return (static_cast<double>(raw) * s.factor + s.offset) * o.scale + o.offset;
}

}  // namespace

void resolve_value_names(Mapping& mapping, std::span<const InputDbc> inputs) {
  for (auto& o : mapping.outputs) {
    if (o.remap_names.empty()) continue;
    std::vector<const DbcSignal*> signals;
    std::vector<std::string> keys;
    std::vector<const Database*> dbs;
    for (const auto& key : o.sources) {
      if (is_modbus_source(key)) continue;
      const InputSource src = resolve_input_source(inputs, key, mapping.file, o.line);
      signals.push_back(&src.dbc.dbc_signal());
      keys.push_back(key);
      dbs.push_back(inputs[static_cast<std::size_t>(src.input)].db);
    }
    for (const auto& n : o.remap_names) {
      if (signals.empty())
        throw MappingError(mapping.file, n.line, "value name '" + n.name + "' needs a DBC source with a VAL_ table; [" + o.name + "] has none");
      std::vector<double> values;  // a name may label several raw values
      for (std::size_t i = 0; i < signals.size(); ++i) {
        std::vector<double> here;
        for (const auto& [raw, name] : signals[i]->choices)
          if (name == n.name) here.push_back(section_value(o, *signals[i], raw));
        if (here.empty())
          throw MappingError(mapping.file, n.line, "'" + n.name + "' is not a value name of " + keys[i] + " in " +
                                                       (dbs[i] ? dbs[i]->file : std::string("the DBC")) + "; " + known_names(*signals[i]));
        if (i == 0) values = here;
        else if (here != values)
          throw MappingError(mapping.file, n.line, "value name '" + n.name + "' means other values in " + keys[i] + " than in " + keys[0]);
      }
      for (double v : values) o.remap.emplace_back(v, n.to);
    }
    o.remap_names.clear();
  }
}

void resolve_value_names(Mapping& mapping, const Database* db) {
  const InputDbc only{"", db};
  resolve_value_names(mapping, std::span<const InputDbc>(&only, 1));
}

}  // namespace meter::controller
