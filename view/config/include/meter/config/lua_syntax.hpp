// The scene-script check the config parser runs on every script's code: Lua text only, compiled
// and never run.
#pragma once

#include <string>
#include <string_view>

namespace meter::config {

// Compiles `code` as Lua text (never bytecode) without running it. Returns "" when it compiles,
// else Lua's message ("<chunk>:<line>: <what>").
std::string lua_syntax_error(std::string_view code, const std::string& chunk_name);

}  // namespace meter::config
