// The map file's end-to-end protection sections: [e2e] (detection from the DBC's conventions and
// the mismatch report's threshold) and one [e2e MESSAGE] (or [e2e INPUT.MESSAGE]) per protected
// message (its checksum algorithm, signals, data id and counter tolerances). Format: docs/e2e.md.
// Every mistake is a MappingError naming the file, the line and what was expected.
#pragma once

#include <string>
#include <string_view>

#include "meter/controller/e2e/e2e_config.hpp"

namespace meter::controller {

// A key of [e2e]: detect, mismatch_ratio, mismatch_frames.
void set_e2e_key(E2eSettings& settings, const std::string& key, std::string_view value, const std::string& file, int line);
// A key of [e2e MESSAGE]: checksum, checksum_signal, counter_signal, data_id, data_id_mode,
// data_ids, max_delta, sync_frames, max_repeated.
void set_e2e_message_key(E2eSpec& spec, const std::string& key, std::string_view value, const std::string& file, int line);
// What only the whole section can say: the keys its algorithm needs, and no key it ignores.
void check_e2e_message(const E2eSpec& spec, const std::string& file);

}  // namespace meter::controller
