// The --input argument to an input backend. This is where the mapping becomes input configuration:
// the kernel id filter from the DBC messages the mapping reads, the Modbus register table from
// its [modbus] sections. The input stage itself knows nothing about mappings.
#pragma once

#include <cstdint>
#include <memory>
#include <ostream>
#include <utility>
#include <vector>

#include "meter/controller/dbc/database.hpp"
#include "meter/controller/input/input.hpp"
#include "meter/controller/input/socketcan.hpp"
#include "meter/controller/mapping/mapping.hpp"
#include "meter/controller/run/commands.hpp"

namespace meter::controller {

// Kernel filter for the messages the mapping reads: exact ids, and for a J1939 message its
// parameter group (any priority and source address), as the DBC matches such messages.
std::vector<CanIdFilter> can_filters(const std::vector<std::pair<std::uint32_t, bool>>& used_ids, const Database* db);

// log:FILE | can:IFACE | modbus-tcp:HOST:PORT | modbus-rtu:DEV:BAUD[:8N1]. Throws SocketCanError
// when the kernel or interface cannot do CAN, std::runtime_error / std::invalid_argument otherwise.
std::unique_ptr<Input> open_input(const RunOptions& options, const Mapping& map, const std::vector<CanIdFilter>& filter,
                                  std::ostream& err);

}  // namespace meter::controller
