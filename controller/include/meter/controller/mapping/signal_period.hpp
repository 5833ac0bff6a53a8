// How often one DBC signal arrives, for deadline monitoring ('timeout = auto'): a plain signal comes
// with every frame of its message, a multiplexed one only with the frames of its own page(s).
#pragma once

#include <optional>

#include "meter/controller/dbc/database.hpp"

namespace meter::controller {

// The arrival period of m.signals[signal] in milliseconds, nullopt when the message has no cycle
// time. A plain signal (or a multiplexor): the message's GenMsgCycleTime. A multiplexed signal: its
// switch's period times the longest run of frames without its page, assuming the sender sends each of
// the N pages the DBC defines for that switch once per round: a signal present on k of them waits at
// most N - k + 1 frames (exactly N for a signal on one page). Nested multiplexing multiplies through
// the switch's own period. Saturates instead of overflowing for absurd page counts.
std::optional<int> signal_period_ms(const DbcMessage& m, int signal);

}  // namespace meter::controller
