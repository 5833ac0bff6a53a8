// E2E protection read from a DBC's conventions: opendbc names a message's checksum CHECKSUM (or
// Checksum, CRC, CHKSUM) and its alive counter COUNTER, and its file name says the make
// (toyota_*, honda_*, vw_mqb_*, subaru_global_*, ...), which says the checksum algorithm; its Tesla
// files name them after the message instead (DAS_controlChecksum, DAS_controlCounter). Pure:
// a parsed DBC in, the specs and a report of what was chosen out.
#pragma once

#include <string>
#include <vector>

#include "meter/controller/dbc/database.hpp"
#include "meter/controller/e2e/e2e_config.hpp"

namespace meter::controller {

struct E2eDetection {
  std::string make;  // "Subaru (pre-global)"; empty: the file name names no make known here
  ChecksumKind checksum = ChecksumKind::None;  // the make's algorithm
  std::vector<E2eSpec> messages;  // one per message with a checksum or counter signal
  std::vector<std::string> notes;  // what was chosen for which message, and what was left out
};

E2eDetection detect_e2e(const Database& db);

}  // namespace meter::controller
