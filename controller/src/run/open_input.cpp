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

std::unique_ptr<Input> open_input(const RunOptions& o, const Mapping& map, const std::vector<CanIdFilter>& filter,
                                  std::ostream& err) {
  if (o.input.rfind("log:", 0) == 0) {
    std::string path = o.input.substr(4);
    ParsedLog log = load_candump_log(path);
    report_bad_lines(log, path, err);
    if (log.frames.empty()) throw std::runtime_error(path + ": no frames in the log");
    return std::make_unique<LogReplay>(std::move(log), parse_replay(o.replay));
  }
  if (o.input.rfind("can:", 0) == 0) return std::make_unique<SocketCanInput>(o.input.substr(4), filter);
  if (o.input.rfind("modbus-tcp:", 0) == 0 || o.input.rfind("modbus-rtu:", 0) == 0) {
    if (!map.modbus) throw std::runtime_error(o.map + ": a Modbus input needs a [modbus] section with registers");
    return std::make_unique<ModbusInput>(o.input.substr(7), *map.modbus);
  }
  throw std::invalid_argument("--input: expected log:FILE, can:IFACE, modbus-tcp:HOST:PORT or modbus-rtu:DEV:BAUD, got '" +
                              o.input + "'");
}

}  // namespace meter::controller
