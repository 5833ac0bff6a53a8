// The --input arguments to input backends: every log loaded and the logs merged into one replay,
// every live input opened by its scheme's factory (run/input_schemes.hpp), several inputs put on
// one clock. This is where the mapping becomes input configuration: the kernel id filter from the
// DBC messages the mapping reads on each bus, the Modbus register table from its [modbus]
// sections. The input stage itself knows nothing about mappings.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "meter/controller/dbc/database.hpp"
#include "meter/controller/input/can_id_filter.hpp"
#include "meter/controller/input/input.hpp"
#include "meter/controller/mapping/mapping.hpp"
#include "meter/controller/model/model.hpp"
#include "meter/controller/run/input_specs.hpp"

namespace meter::controller {

// Kernel filter for the messages the mapping reads: exact ids, and for a J1939 message its
// parameter group (any priority and source address), as the DBC matches such messages.
std::vector<CanIdFilter> can_filters(const std::vector<std::pair<std::uint32_t, bool>>& used_ids, const Database* db);

// Opens every input: one as itself; several candump logs as one replay of the merged logs; logs
// and live inputs (or several live ones) as an InputSet on the clock of the (merged) log, else of
// the first input. dbs[i] is specs[i]'s database (empty: none). A log among live inputs replays in
// real time only: a faster clock could not be one time base with a live bus. Throws
// SocketCanError when the kernel or interface cannot do CAN, std::runtime_error /
// std::invalid_argument otherwise.
std::unique_ptr<Input> open_inputs(const std::vector<InputSpec>& specs, const std::vector<std::optional<Database>>& dbs,
                                   const std::string& replay, const Mapping& map, const Model& model, std::ostream& err);

}  // namespace meter::controller
