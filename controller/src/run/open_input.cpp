#include "open_input.hpp"

#include <stdexcept>
#include <string>

#include "command_output.hpp"
#include "meter/controller/input/log_replay.hpp"
#include "meter/controller/input/merge_logs.hpp"
#include "meter/controller/run/input_schemes.hpp"
#include "meter/controller/run/input_set.hpp"

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

// The log opened up to its first frame (a log without one is refused there), its bad lines
// reported on err as the replay meets them.
std::unique_ptr<LogSource> open_log(const InputSpec& s, std::ostream& err) {
  std::unique_ptr<LogSource> log = s.scheme->load(s.address);
  report_bad_lines(*log, s.address, err);
  return log;
}

// A live input (SocketCAN, Modbus, ...) of input index i, opened by its scheme.
std::unique_ptr<Input> open_live(const InputSpec& s, int i, const Database* db, const Mapping& map, const Model& model) {
  return s.scheme->open(LiveInputContext{s.address, i, s.name, db, map, model});
}

}  // namespace

std::unique_ptr<Input> open_inputs(const std::vector<InputSpec>& specs, const std::vector<std::optional<Database>>& dbs,
                                   const std::string& replay, const Mapping& map, const Model& model, std::ostream& err) {
  auto db_of = [&](std::size_t i) { return dbs[i] ? &*dbs[i] : nullptr; };
  check_modbus_tables(specs, map);
  if (specs.size() == 1) {
    if (specs[0].kind() == InputKind::Log) return std::make_unique<LogReplay>(open_log(specs[0], err), parse_replay(replay));
    return open_live(specs[0], 0, db_of(0), map, model);
  }
  std::vector<std::pair<int, std::unique_ptr<LogSource>>> logs;
  std::string log_names;
  for (std::size_t i = 0; i < specs.size(); ++i)
    if (specs[i].kind() == InputKind::Log) {
      logs.emplace_back(static_cast<int>(i), open_log(specs[i], err));
      log_names += (log_names.empty() ? "" : "+") + specs[i].name;
    }
  const ReplayOptions replay_options = parse_replay(replay);
  if (logs.size() == specs.size()) return std::make_unique<LogReplay>(std::make_unique<MergedLogSource>(std::move(logs)), replay_options);

  std::vector<InputSet::Member> members;
  if (!logs.empty()) {
    if (replay_options.mode != ReplayMode::Realtime)
      throw std::invalid_argument("--replay " + replay + ": with a live input (can:, modbus-) the logs replay in realtime only, "
                                  "so that all inputs share one clock");
    members.push_back({std::make_unique<LogReplay>(std::make_unique<MergedLogSource>(std::move(logs)), replay_options), log_names, -1});
  }
  for (std::size_t i = 0; i < specs.size(); ++i) {
    if (specs[i].kind() == InputKind::Log) continue;
    members.push_back({open_live(specs[i], static_cast<int>(i), db_of(i), map, model), specs[i].name, static_cast<int>(i)});
  }
  return std::make_unique<InputSet>(std::move(members));
}

}  // namespace meter::controller
