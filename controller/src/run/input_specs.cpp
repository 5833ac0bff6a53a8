// --input [NAME=]TARGET and --dbc [NAME=]FILE paired into one spec per input.
#include <algorithm>
#include <cctype>
#include <stdexcept>

#include "meter/controller/run/input_specs.hpp"

namespace meter::controller {
namespace {

// "NAME=REST" when the text before the first '=' is an identifier; otherwise no name (so
// "log:/a=b.log" is a target, not the input "log:/a").
std::pair<std::string, std::string> split_name(const std::string& arg) {
  const auto eq = arg.find('=');
  if (eq == std::string::npos || eq == 0) return {"", arg};
  const std::string name = arg.substr(0, eq);
  const bool ident = (std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_') &&
                     std::all_of(name.begin(), name.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
  if (!ident) return {"", arg};
  return {name, arg.substr(eq + 1)};
}

}  // namespace

std::vector<InputSpec> parse_input_specs(const std::vector<std::string>& inputs, const std::vector<std::string>& dbcs) {
  if (inputs.empty()) throw std::invalid_argument("--input: expected at least one input");
  if (inputs.size() > 255) throw std::invalid_argument("--input: at most 255 inputs");
  std::vector<InputSpec> specs;
  for (const std::string& arg : inputs) {
    auto [name, target] = split_name(arg);
    InputTarget parsed = parse_input_target(target);
    InputSpec s{name, target, "", parsed.scheme, std::move(parsed.address)};
    if (inputs.size() > 1 && name.empty())
      throw std::invalid_argument("--input " + arg + ": with several inputs each one needs a name, e.g. --input body=" + arg);
    if (name == "modbus")
      throw std::invalid_argument("--input " + arg + ": 'modbus' is reserved for the mapping's modbus.NAME sources; choose another name");
    for (const InputSpec& o : specs)
      if (!name.empty() && o.name == name) throw std::invalid_argument("--input " + arg + ": a second input named '" + name + "'");
    specs.push_back(std::move(s));
  }

  for (const std::string& arg : dbcs) {
    auto [name, file] = split_name(arg);
    InputSpec* owner = nullptr;
    if (specs.size() == 1 && (name.empty() || name == specs[0].name)) {
      owner = &specs[0];
    } else if (name.empty()) {
      throw std::invalid_argument("--dbc " + arg + ": with several inputs each DBC names its input, e.g. --dbc " +
                                  specs[0].name + "=" + arg);
    } else {
      for (InputSpec& s : specs)
        if (s.name == name) owner = &s;
    }
    if (!owner) {
      std::string names;
      for (const InputSpec& s : specs) names += (names.empty() ? "" : ", ") + (s.name.empty() ? "(unnamed)" : s.name);
      throw std::invalid_argument("--dbc " + arg + ": no input named '" + name + "' (inputs: " + names + ")");
    }
    if (!owner->dbc.empty())
      throw std::invalid_argument("--dbc " + arg + ": input " + (owner->name.empty() ? "" : "'" + owner->name + "' ") +
                                  "already has the DBC " + owner->dbc);
    if (file.empty()) throw std::invalid_argument("--dbc " + arg + ": expected a file after '='");
    owner->dbc = file;
  }
  if (specs.size() > 1)
    for (const InputSpec& s : specs) {
      if (s.kind() != InputKind::Modbus && s.dbc.empty())
        throw std::invalid_argument("--input " + s.name + "=" + s.target + ": a CAN input needs its DBC: --dbc " + s.name + "=FILE");
      if (s.kind() == InputKind::Modbus && !s.dbc.empty())
        throw std::invalid_argument("--dbc " + s.name + "=" + s.dbc +
                                    ": a Modbus input reads the mapping's [modbus] registers, not a DBC");
    }
  return specs;
}

void check_modbus_tables(const std::vector<InputSpec>& specs, const Mapping& map) {
  std::vector<const InputSpec*> modbus;
  for (const InputSpec& s : specs)
    if (s.kind() == InputKind::Modbus) modbus.push_back(&s);
  if (modbus.empty()) return;
  std::string names;
  for (const InputSpec* s : modbus) {
    names += (names.empty() ? "" : ", ") + (s->name.empty() ? "(unnamed)" : s->name);
    if (modbus.size() > 1 && !map.modbus_inputs.contains(s->name))
      throw std::invalid_argument("--input " + s->name + "=" + s->target + ": with several Modbus inputs each reads its own registers: " +
                                  map.file + " needs [modbus " + s->name + "] and [modbus.register " + s->name + ".NAME] sections");
  }
  for (const auto& entry : map.modbus_inputs) {
    const std::string& input = entry.first;
    if (std::none_of(modbus.begin(), modbus.end(), [&](const InputSpec* s) { return s->name == input; }))
      throw std::invalid_argument(map.file + ": [modbus " + input + "]: no Modbus input is named '" + input +
                                  "' (Modbus inputs: " + names + "); expected --input " + input + "=modbus-tcp:HOST:PORT or modbus-rtu:DEV:BAUD");
  }
}

}  // namespace meter::controller
