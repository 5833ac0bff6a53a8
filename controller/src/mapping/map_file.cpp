// Mapping file parser: INI-like sections, one per catalog signal, plus [global], [modbus] /
// [modbus INPUT], [modbus.register [INPUT.]NAME], [e2e] and [e2e MESSAGE] (e2e_section.hpp). Every
// error names file:line and what was expected.
#include "meter/controller/mapping/map_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <sstream>

#include "meter/controller/mapping/e2e_section.hpp"
#include "meter/controller/mapping/mapping.hpp"

namespace meter::controller {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

std::vector<std::string> words(std::string_view s) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == ' ' || c == '\t' || c == ',') {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

struct Ctx {
  const std::string& file;
  int line;
  [[noreturn]] void fail(const std::string& what) const { throw MappingError(file, line, what); }
  double number(std::string_view text, const std::string& key) const {
    std::string t(trim(text));
    char* end = nullptr;
    double v = std::strtod(t.c_str(), &end);
    if (t.empty() || end != t.c_str() + t.size() || !std::isfinite(v))
      fail(key + ": expected a number, got '" + t + "'");
    return v;
  }
  // "0.5", "500ms", "2s"
  double seconds(std::string_view text, const std::string& key) const {
    std::string t(trim(text));
    double scale = 1.0;
    if (t.size() > 2 && t.substr(t.size() - 2) == "ms") {
      scale = 1e-3;
      t.resize(t.size() - 2);
    } else if (t.size() > 1 && t.back() == 's') {
      t.pop_back();
    }
    double v = number(t, key) * scale;
    // Bounded so every duration converts to int64 nanoseconds without overflow.
    if (v < 0 || v > 1e6) fail(key + ": expected a duration from 0 to 1e6 s, got '" + std::string(text) + "'");
    return v;
  }
  bool boolean(std::string_view text, const std::string& key) const {
    auto t = trim(text);
    if (t == "true" || t == "yes" || t == "1") return true;
    if (t == "false" || t == "no" || t == "0") return false;
    fail(key + ": expected true or false, got '" + std::string(t) + "'");
  }
};

struct Conversion {
  const char* name;
  double scale, offset;
};
constexpr Conversion kConversions[] = {
    {"m/s->km/h", 3.6, 0.0},          {"km/h->m/s", 1 / 3.6, 0.0},        {"mph->km/h", 1.609344, 0.0},
    {"kelvin->celsius", 1.0, -273.15}, {"K->celsius", 1.0, -273.15},       {"degK->celsius", 1.0, -273.15},
    {"fahrenheit->celsius", 5.0 / 9.0, -160.0 / 9.0},                    {"rad/s->rpm", 30.0 / std::numbers::pi, 0.0},
    {"ratio->percent", 100.0, 0.0},   {"permille->percent", 0.1, 0.0},
};

// Items of a value list, comma separated; an item is a number or a DBC value name, which may hold
// blanks ("clutch released") or be quoted ("\"P\"" keeps a name that looks like a number a name).
struct ValueItem {
  std::string text;
  bool quoted;
};
std::vector<ValueItem> value_list(std::string_view value, const Ctx& c) {
  std::vector<ValueItem> out;
  std::string cur;
  bool quoted = false, in_quotes = false;
  auto flush = [&] {
    std::string t(trim(cur));
    if (t.empty() && !quoted) c.fail("expected a value or a DBC value name between the commas");
    out.push_back({t, quoted});
    cur.clear();
    quoted = false;
  };
  for (char ch : value) {
    if (ch == '"') {
      in_quotes = !in_quotes;
      quoted = true;
    } else if (ch == ',' && !in_quotes) {
      flush();
    } else {
      cur += ch;
    }
  }
  if (in_quotes) c.fail("expected '\"' closing the value name");
  flush();
  return out;
}

// map items: "from:to", the last ':' splits (names may hold one). Items without a comma between
// them are split at blanks when every word is a pair ("14:-1 15:126", as before value names).
std::vector<std::pair<ValueItem, std::string>> value_pairs(std::string_view value, const Ctx& c) {
  std::vector<std::pair<ValueItem, std::string>> out;
  for (const auto& item : value_list(value, c)) {
    auto parts = words(item.text);
    bool all_pairs = !item.quoted && parts.size() > 1;
    for (const auto& p : parts) all_pairs = all_pairs && p.find(':') != std::string::npos;
    if (!all_pairs) parts = {item.text};
    for (const auto& p : parts) {
      auto colon = p.rfind(':');
      if (colon == std::string::npos) c.fail("map: expected 'from:to' pairs, got '" + p + "'");
      out.push_back({ValueItem{std::string(trim(std::string_view(p).substr(0, colon))), item.quoted}, p.substr(colon + 1)});
    }
  }
  return out;
}

// A number is a source value; anything else (or a quoted text) a DBC value name.
void add_value(OutputMapping& o, const ValueItem& from, double to, const Ctx& c) {
  if (from.text.empty()) c.fail("map: expected a value or a DBC value name before ':'");
  // An enum's catalog range is the set of states the view knows: a state outside it is a typo.
  const protocol::SignalInfo* info = protocol::find_signal(o.id);
  if (info->kind == protocol::SignalKind::Enum && (to < info->min || to > info->max)) {
    char range[96];
    std::snprintf(range, sizeof range, "%g is outside the catalog range %g..%g", to, info->min, info->max);
    c.fail("map: " + from.text + ":" + range + " of " + o.name);
  }
  char* end = nullptr;
  double v = std::strtod(from.text.c_str(), &end);
  if (!from.quoted && end == from.text.c_str() + from.text.size() && std::isfinite(v)) o.remap.emplace_back(v, to);
  else o.remap_names.push_back({from.text, to, c.line});
}

// Where the value comes from and how it becomes the catalog value: sources, combine, conversion,
// value maps, the range rule. False: not one of these keys.
bool set_value_key(OutputMapping& o, const std::string& key, std::string_view value, const Ctx& c) {
  const auto w = words(value);
  if (key == "source") {
    if (w.empty()) c.fail("source: expected Message.Signal, INPUT.Message.Signal or modbus.NAME (comma separated for several)");
    for (auto& s : w)
      if (s.find('.') == std::string::npos || s.front() == '.' || s.back() == '.')
        c.fail("source: expected Message.Signal, INPUT.Message.Signal or modbus.NAME, got '" + s + "'");
    o.sources = w;
  } else if (key == "combine") {
    std::string v(trim(value));
    if (v == "first") o.combine = Combine::First;
    else if (v == "mean") o.combine = Combine::Mean;
    else if (v == "min") o.combine = Combine::Min;
    else if (v == "max") o.combine = Combine::Max;
    else c.fail("combine: expected first, mean, min or max, got '" + v + "'");
  } else if (key == "convert") {
    std::string v;
    for (char ch : value)
      if (ch != ' ' && ch != '\t') v += ch;
    for (auto& k : kConversions)
      if (v == k.name) {
        o.scale = k.scale;
        o.offset = k.offset;
        return true;
      }
    std::string known;
    for (auto& k : kConversions) known += std::string(known.empty() ? "" : ", ") + k.name;
    c.fail("convert: unknown conversion '" + v + "'; expected one of " + known + " (or use scale/offset)");
  } else if (key == "scale") {
    o.scale = c.number(value, key);
    if (o.scale == 0) c.fail("scale: 0 would erase the signal");
  } else if (key == "offset") {
    o.offset = c.number(value, key);
  } else if (key == "map") {
    o.remap.clear();
    o.remap_names.clear();
    for (const auto& [from, to] : value_pairs(value, c))
      add_value(o, from, c.number(to, key), c);
  } else if (key == "lit_when") {
    // Telltales: lit while the source is one of these values or DBC value names, dark otherwise.
    if (protocol::find_signal(o.id)->kind != protocol::SignalKind::Telltale)
      c.fail("lit_when: only for telltales (Cluster.Telltale.*); use map for " + o.name);
    o.remap.clear();
    o.remap_names.clear();
    for (const auto& item : value_list(value, c)) add_value(o, item, 1.0, c);
    o.remap_default = 0.0;
  } else if (key == "out_of_range") {
    std::string v(trim(value));
    if (v == "invalid") o.out_of_range = RangeAction::Invalid;
    else if (v == "clamp") o.out_of_range = RangeAction::Clamp;
    else if (v == "accept") o.out_of_range = RangeAction::Accept;
    else c.fail("out_of_range: expected invalid, clamp or accept, got '" + v + "'");
  } else {
    return false;
  }
  return true;
}

// When a source counts as lost and what is shown then. False: not one of these keys.
bool set_timeout_key(OutputMapping& o, const std::string& key, std::string_view value, const Ctx& c) {
  if (key == "first_timeout") {
    o.first_timeout_s = c.seconds(value, key);
    return true;
  }
  if (key == "timeout") {
    const std::string_view v = trim(value);
    o.timeout_auto = v == "auto";
    o.timeout_s.reset();
    if (v != "auto" && v != "none") {
      o.timeout_s = c.seconds(value, key);
      if (*o.timeout_s <= 0) c.fail("timeout: expected a duration > 0, 'auto' or 'none'");
    }
    return true;
  }
  if (key != "on_timeout") return false;
  const auto w = words(value);
  if (w.size() == 1 && w[0] == "hold") o.on_timeout = TimeoutAction::Hold;
  else if (w.size() == 1 && w[0] == "invalid") o.on_timeout = TimeoutAction::Invalid;
  else if (w.size() == 2 && w[0] == "substitute") {
    o.on_timeout = TimeoutAction::Substitute;
    o.substitute = c.number(w[1], key);
  } else c.fail("on_timeout: expected hold, invalid or 'substitute <value>'");
  return true;
}

// How the shown value is conditioned: needle damping, the speedometer rule, fuel filtering,
// telltale blink and rules, the odometer. False: not one of these keys.
bool set_conditioning_key(OutputMapping& o, const std::string& key, std::string_view value, const Ctx& c) {
  const auto w = words(value);
  if (key == "needle") {
    o.needle_tau_s = c.seconds(value, key);
    if (o.needle_tau_s <= 0) c.fail("needle: expected the damping time constant in seconds (> 0)");
  } else if (key == "speedometer") {
    if (w.size() != 2) c.fail("speedometer: expected '<ratio> <offset km/h>' (UN R39 over-read)");
    SpeedometerRule r{c.number(w[0], key), c.number(w[1], key)};
    if (r.ratio < 1.0 || r.ratio > 1.1 || r.offset_kmh < 0 || r.offset_kmh > 4)
      c.fail("speedometer: ratio must be 1..1.1 and offset 0..4 km/h to stay within UN R39");
    o.speedometer = r;
  } else if (key == "fuel") {
    o.fuel = c.boolean(value, key);
  } else if (key == "fuel_tau_moving" || key == "fuel_tau_stopped") {
    // The filter divides the tick by it: 0 (or -0, which passes the duration check) is no filter.
    const double tau = c.seconds(value, key);
    if (!(tau > 0)) c.fail(key + ": expected a time constant in seconds (> 0)");
    (key == "fuel_tau_moving" ? o.fuel_config.tau_moving_s : o.fuel_config.tau_stopped_s) = tau;
  } else if (key == "refuel_delta") {
    o.fuel_config.refuel_delta = c.number(value, key);
  } else if (key == "sender_fault_time") {
    o.fuel_config.fault_time_s = c.seconds(value, key);
  } else if (key == "blink") {
    if (w.size() != 2) c.fail("blink: expected '<period s> <duty 0..1>'");
    BlinkPattern b{c.seconds(w[0], key), c.number(w[1], key)};
    if (b.period_s <= 0 || b.duty <= 0 || b.duty >= 1) c.fail("blink: period must be > 0 and duty inside (0, 1)");
    o.blink = b;
  } else if (key == "invert") {
    o.invert = c.boolean(value, key);
  } else if (key == "rule") {
    if (w.size() == 1 && w[0] == "seatbelt") {
      o.rule = Rule::SeatBelt;
    } else if (w.size() == 4 && (w[0] == "below" || w[0] == "above")) {
      o.rule = w[0] == "below" ? Rule::Below : Rule::Above;
      if (!protocol::find_signal(w[1]))
        c.fail("rule: '" + w[1] + "' is not a signal of the catalog " + protocol::active_catalog()->source());
      o.rule_input = w[1];
      o.rule_on = c.number(w[2], key);
      o.rule_off = c.number(w[3], key);
      if ((o.rule == Rule::Below && o.rule_off < o.rule_on) || (o.rule == Rule::Above && o.rule_off > o.rule_on))
        c.fail("rule: the release threshold must lie on the far side of the trigger (hysteresis)");
    } else {
      c.fail("rule: expected 'seatbelt', 'below <catalog signal> <on> <off>' or 'above <catalog signal> <on> <off>'");
    }
  } else if (key == "first_level") {
    o.seat_belt.first_level_s = c.seconds(value, key);
    if (o.seat_belt.first_level_s < 4 || o.seat_belt.first_level_s > 8) c.fail("first_level: expected 4..8 s");
  } else if (key == "accumulate") {
    if (w.size() == 1 && w[0] == "speed") {
      o.accumulate = Accumulate::Speed;
    } else if (w.size() == 4 && w[0] == "counter") {
      o.accumulate = Accumulate::Counter;
      o.sources = {w[1]};
      double bits = c.number(w[2], key);
      if (bits < 1 || bits > 64 || bits != std::floor(bits)) c.fail("accumulate: counter bits must be 1..64");
      o.counter_bits = static_cast<unsigned>(bits);
      o.um_per_count = c.number(w[3], key);
      if (o.um_per_count <= 0) c.fail("accumulate: micrometres per count must be > 0");
    } else {
      c.fail("accumulate: expected 'speed' or 'counter <Message.Signal> <bits> <micrometres per count>'");
    }
  } else {
    return false;
  }
  return true;
}

void set_output_key(OutputMapping& o, const std::string& key, std::string_view value, const Ctx& c) {
  if (set_value_key(o, key, value, c) || set_timeout_key(o, key, value, c) || set_conditioning_key(o, key, value, c)) return;
  c.fail("unknown key '" + key + "'; expected source, combine, convert, scale, offset, map, lit_when, out_of_range, timeout, "
         "first_timeout, on_timeout, needle, speedometer, fuel, blink, invert, rule, first_level, accumulate");
}

RegisterType register_type(const std::string& v, const Ctx& c) {
  if (v == "int16") return RegisterType::Int16;
  if (v == "uint16") return RegisterType::Uint16;
  if (v == "int32") return RegisterType::Int32;
  if (v == "uint32") return RegisterType::Uint32;
  if (v == "float32") return RegisterType::Float32;
  c.fail("type: expected int16, uint16, int32, uint32 or float32, got '" + v + "'");
}

enum class Section { None, Global, Modbus, Register, Output, E2e, E2eMessage };

// The register table [modbus.register REG] adds to: REG "NAME" goes into [modbus]'s, "INPUT.NAME"
// into the table of the Modbus input named INPUT; `reg` is left holding NAME.
ModbusConfig& register_table(Mapping& m, std::string& reg, const Ctx& c) {
  const auto dot = reg.find('.');
  if (dot == std::string::npos) {
    if (!m.modbus) m.modbus.emplace();
    return *m.modbus;
  }
  const std::string input = reg.substr(0, dot);
  reg = reg.substr(dot + 1);
  if (input.empty() || reg.empty() || reg.find('.') != std::string::npos)
    c.fail("expected [modbus.register NAME] or [modbus.register INPUT.NAME]");
  ModbusConfig& t = m.modbus_inputs[input];
  t.input = input;
  return t;
}

// A [section] header: the section it opens (a catalog signal's output, a Modbus register, ...);
// `table` is the Modbus table a [modbus ...] or [modbus.register ...] section fills.
Section open_section(Mapping& m, std::string_view header, const Ctx& c, ModbusConfig*& table) {
  if (header.back() != ']') c.fail("expected ']' closing the section header");
  std::string name(trim(header.substr(1, header.size() - 2)));
  if (name == "global") {
    return Section::Global;
  } else if (name == "modbus") {
    if (!m.modbus) m.modbus.emplace();
    table = &*m.modbus;
    return Section::Modbus;
  } else if (name.rfind("modbus ", 0) == 0) {
    const std::string input(trim(std::string_view(name).substr(7)));
    if (input.empty() || input.find_first_of(". \t") != std::string::npos) c.fail("expected [modbus INPUT], INPUT an --input name");
    table = &m.modbus_inputs[input];
    table->input = input;
    return Section::Modbus;
  } else if (name.rfind("modbus.register", 0) == 0) {
    std::string reg(trim(std::string_view(name).substr(15)));
    if (reg.empty()) c.fail("expected [modbus.register NAME]");
    table = &register_table(m, reg, c);
    if (table->find(reg)) c.fail("register '" + reg + "' defined twice");
    ModbusRegister r;
    r.name = reg;
    r.line = c.line;
    table->registers.push_back(r);
    return Section::Register;
  } else if (name == "e2e") {
    return Section::E2e;
  } else if (name.rfind("e2e ", 0) == 0 || name.rfind("e2e\t", 0) == 0) {
    E2eSpec spec;
    spec.message = std::string(trim(std::string_view(name).substr(4)));
    if (spec.message.empty() || spec.message.find_first_of(" \t") != std::string::npos)
      c.fail("expected [e2e MESSAGE] or [e2e INPUT.MESSAGE], got [" + name + "]");
    for (const E2eSpec& other : m.e2e.messages)
      if (other.message == spec.message) c.fail("section [e2e " + spec.message + "] appears twice");
    spec.line = c.line;
    spec.origin = "map file " + m.file + ":" + std::to_string(c.line);
    m.e2e.messages.push_back(spec);
    return Section::E2eMessage;
  } else {
    const protocol::SignalInfo* info = protocol::find_signal(name);
    if (!info)
      c.fail("section [" + name + "]: expected a signal of the catalog " + protocol::active_catalog()->source() +
             " (e.g. Vehicle.Speed), 'global', 'modbus', 'modbus INPUT', 'modbus.register [INPUT.]NAME', 'e2e' or 'e2e MESSAGE'");
    if (m.find(info->id)) c.fail("section [" + name + "] appears twice");
    OutputMapping o;
    o.id = info->id;
    o.name = name;
    o.line = c.line;
    m.outputs.push_back(o);
    return Section::Output;
  }
}

// [global]: the bulb check, the odometer's persist interval, the model's update period.
void set_global_key(Mapping& m, const std::string& key, std::string_view value, const Ctx& c) {
  if (key == "bulb_check") {
    m.bulb_check_s = c.seconds(value, key);
    if (m.bulb_check_s < 2 || m.bulb_check_s > 4) c.fail("bulb_check: expected 2..4 s");
  } else if (key == "persist_interval") {
    m.persist_interval_s = c.seconds(value, key);
    if (m.persist_interval_s <= 0) c.fail("persist_interval: expected > 0 s");
  } else if (key == "update_period") {
    m.update_period_s = c.seconds(value, key);
    if (m.update_period_s < 0.001 || m.update_period_s > 1) c.fail("update_period: expected 1 ms..1 s");
  } else {
    c.fail("unknown [global] key '" + key + "'; expected bulb_check, persist_interval or update_period");
  }
}

// [modbus]: the poll settings of the Modbus input.
void set_modbus_key(ModbusConfig& modbus, const std::string& key, std::string_view value, const Ctx& c) {
  if (key == "poll") modbus.poll_s = c.seconds(value, key);
  else if (key == "timeout") modbus.response_timeout_s = c.seconds(value, key);
  else if (key == "unit") {
    double u = c.number(value, key);
    if (u < 0 || u > 247 || u != std::floor(u)) c.fail("unit: expected a Modbus unit id 0..247");
    modbus.unit_id = static_cast<int>(u);
  }
  else if (key == "heartbeat") modbus.heartbeat = std::string(value);
  else if (key == "stale_after") {
    double n = c.number(value, key);
    if (n < 1 || n > 100000 || n != std::floor(n)) c.fail("stale_after: expected a poll count 1..100000");
    modbus.stale_after_polls = static_cast<int>(n);
  }
  else c.fail("unknown [modbus] key '" + key + "'; expected poll, timeout, unit, heartbeat or stale_after");
  if (modbus.poll_s <= 0 || modbus.response_timeout_s <= 0) c.fail(key + ": expected a duration > 0");
}

// [modbus.register NAME]: where the register is and how its words become a value.
void set_register_key(ModbusRegister& r, const std::string& key, std::string_view value, const Ctx& c) {
  if (key == "table") {
    if (value == "holding") r.input_table = false;
    else if (value == "input") r.input_table = true;
    else c.fail("table: expected holding or input");
  } else if (key == "address") {
    double a = c.number(value, key);
    if (a < 0 || a > 65535 || a != std::floor(a)) c.fail("address: expected 0..65535");
    r.address = static_cast<int>(a);
  } else if (key == "type") {
    r.type = register_type(std::string(value), c);
  } else if (key == "word_order") {
    if (value == "high_first") r.word_swap = false;
    else if (value == "low_first") r.word_swap = true;
    else c.fail("word_order: expected high_first or low_first");
  } else if (key == "scale") {
    r.scale = c.number(value, key);
  } else if (key == "offset") {
    r.offset = c.number(value, key);
  } else {
    c.fail("unknown register key '" + key + "'; expected table, address, type, word_order, scale or offset");
  }
}

// Cross-checks that need the whole file: every output has what it needs, every Modbus name resolves.
void check_mapping(const Mapping& m, Ctx& c) {
  for (const auto& o : m.outputs) {
    c.line = o.line;
    const bool needs_source = o.rule == Rule::None && o.accumulate == Accumulate::None;
    if (needs_source && o.sources.empty()) c.fail("[" + o.name + "]: expected a 'source', 'rule' or 'accumulate' key");
    if (o.rule == Rule::SeatBelt && o.sources.empty()) c.fail("[" + o.name + "]: rule seatbelt needs 'source' = the unbuckled signal");
    if (o.accumulate != Accumulate::None && o.name != protocol::vss::kOdometer)
      c.fail("[" + o.name + "]: accumulate belongs to " + std::string(protocol::vss::kOdometer));
    if (o.accumulate == Accumulate::Speed &&
        std::none_of(m.outputs.begin(), m.outputs.end(), [](const OutputMapping& x) { return x.name == protocol::vss::kSpeed; }))
      c.fail("[" + o.name + "]: accumulate speed needs a [" + std::string(protocol::vss::kSpeed) + "] section");
    for (const auto& s : o.sources)
      if (s.rfind("modbus.", 0) == 0 && !m.modbus_table_of(s))
        c.fail("[" + o.name + "]: source " + s + " names no [modbus.register " + s.substr(7) + "]");
  }
  for (const E2eSpec& spec : m.e2e.messages) check_e2e_message(spec, m.file);
  auto check_heartbeat = [&](const ModbusConfig& t) {
    if (!t.heartbeat.empty() && !t.find(t.heartbeat))
      throw MappingError(m.file, 0, "[modbus" + (t.input.empty() ? "" : " " + t.input) + "] heartbeat '" + t.heartbeat + "' names no register");
  };
  if (m.modbus) check_heartbeat(*m.modbus);
  for (const auto& [input, t] : m.modbus_inputs) check_heartbeat(t);
}

}  // namespace

Mapping parse_mapping(std::string_view text, const std::string& file) {
  Mapping m;
  m.file = file;
  Section sec = Section::None;
  ModbusConfig* table = nullptr;  // the Modbus table the current [modbus ...] section fills
  Ctx c{file, 0};
  std::istringstream in{std::string(text)};
  std::string raw;
  while (std::getline(in, raw)) {
    ++c.line;
    std::string_view line = raw;
    auto hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    line = trim(line);
    if (line.empty()) continue;
    if (line.front() == '[') {
      sec = open_section(m, line, c, table);
      continue;
    }
    auto eq = line.find('=');
    if (eq == std::string_view::npos) c.fail("expected 'key = value' or a [section] header");
    std::string key(trim(line.substr(0, eq)));
    std::string_view value = trim(line.substr(eq + 1));
    if (value.empty()) c.fail(key + ": expected a value after '='");
    switch (sec) {
      case Section::None: c.fail("'" + key + "' outside any [section]");
      case Section::Global: set_global_key(m, key, value, c); break;
      case Section::Modbus: set_modbus_key(*table, key, value, c); break;
      case Section::Register: set_register_key(table->registers.back(), key, value, c); break;
      case Section::Output: set_output_key(m.outputs.back(), key, value, c); break;
      case Section::E2e: set_e2e_key(m.e2e, key, value, file, c.line); break;
      case Section::E2eMessage: set_e2e_message_key(m.e2e.messages.back(), key, value, file, c.line); break;
    }
  }
  check_mapping(m, c);
  return m;
}

Mapping load_mapping(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MappingError(path, 0, "cannot open the mapping file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_mapping(ss.str(), path);
}

}  // namespace meter::controller
