// Several recorded logs (two buses logged on one clock) as one log for one replay.
#pragma once

#include <utility>
#include <vector>

#include "meter/controller/input/candump_log.hpp"

namespace meter::controller {

// Several logs as one: every frame tagged with its log's input index (the first of each
// pair), all frames in timestamp order, each file's own order kept where its timestamps tie or
// step back. The logs were recorded on one clock, so their relative timing is kept exactly.
ParsedLog merge_logs(std::vector<std::pair<int, ParsedLog>> logs);

}  // namespace meter::controller
