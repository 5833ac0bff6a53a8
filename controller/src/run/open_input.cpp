#include "open_input.hpp"

#include <stdexcept>
#include <string>

#include "command_output.hpp"
#include "meter/controller/input/candump_log.hpp"
#include "meter/controller/input/log_replay.hpp"
#include "meter/controller/input/modbus_input.hpp"

namespace meter::controller {

std::vector<CanIdFilter> can_filters(const std::vector<std::pair<std::uint32_t, bool>>& used_ids, const Database* db) {
  std::vector<CanIdFilter> filter;
  for (const auto& [id, extended] : used_ids) {
    const DbcMessage* m = db ? db->find(id, extended) : nullptr;
    filter.push_back(m && m->j1939 ? j1939_group_filter(id) : CanIdFilter{id, extended});
  }
  return filter;
}

namespace {

ParsedLog load_log(const std::string& path, std::ostream& err) {
  ParsedLog log = load_candump_log(path);
  report_bad_lines(log, path, err);
  if (log.frames.empty()) throw std::runtime_error(path + ": no frames in the log");
  return log;
}

// A live input (SocketCAN, Modbus) of input index i.
std::unique_ptr<Input> open_live(const InputSpec& s, int i, const Database* db, const Mapping& map, const Model& model) {
  if (s.kind == InputKind::SocketCan) return std::make_unique<SocketCanInput>(s.target.substr(4), can_filters(model.used_ids(i), db));
  if (!map.modbus) throw std::runtime_error(map.file + ": a Modbus input needs a [modbus] section with registers");
  return std::make_unique<ModbusInput>(s.target.substr(7), *map.modbus);
}

}  // namespace

std::unique_ptr<Input> open_inputs(const std::vector<InputSpec>& specs, const std::vector<std::optional<Database>>& dbs,
                                   const std::string& replay, const Mapping& map, const Model& model, std::ostream& err) {
  auto db_of = [&](std::size_t i) { return dbs[i] ? &*dbs[i] : nullptr; };
  if (specs.size() == 1) {
    if (specs[0].kind == InputKind::Log)
      return std::make_unique<LogReplay>(load_log(specs[0].target.substr(4), err), parse_replay(replay));
    return open_live(specs[0], 0, db_of(0), map, model);
  }
  std::vector<std::pair<int, ParsedLog>> logs;
  std::string log_names;
  for (std::size_t i = 0; i < specs.size(); ++i)
    if (specs[i].kind == InputKind::Log) {
      logs.emplace_back(static_cast<int>(i), load_log(specs[i].target.substr(4), err));
      log_names += (log_names.empty() ? "" : "+") + specs[i].name;
    }
  const ReplayOptions replay_options = parse_replay(replay);
  if (logs.size() == specs.size()) return std::make_unique<LogReplay>(merge_logs(std::move(logs)), replay_options);

  std::vector<InputSet::Member> members;
  if (!logs.empty()) {
    if (replay_options.mode != ReplayMode::Realtime)
      throw std::invalid_argument("--replay " + replay + ": with a live input (can:, modbus-) the logs replay in realtime only, "
                                  "so that all inputs share one clock");
    members.push_back({std::make_unique<LogReplay>(merge_logs(std::move(logs)), replay_options), log_names, -1, -1});
  }
  for (std::size_t i = 0; i < specs.size(); ++i) {
    if (specs[i].kind == InputKind::Log) continue;
    auto in = open_live(specs[i], static_cast<int>(i), db_of(i), map, model);
    const int fd = specs[i].kind == InputKind::SocketCan ? static_cast<SocketCanInput&>(*in).fd() : -1;
    members.push_back({std::move(in), specs[i].name, static_cast<int>(i), fd});
  }
  return std::make_unique<InputSet>(std::move(members));
}

}  // namespace meter::controller
