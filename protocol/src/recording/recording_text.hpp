// The lexical pieces of a recording line shared by its writer and its reader: quoted texts,
// CLOSE reasons as single words, and splitting a line into space-separated tokens.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "meter/protocol/wire.hpp"

namespace meter::protocol::detail {

// "text" with \\, \" and \xHH for control bytes; other bytes (UTF-8) as they are.
void append_quoted(std::string& out, std::string_view text);
// The inverse of append_quoted for a whole token; std::nullopt plus `why` when it is not one.
std::optional<std::string> unquote(std::string_view token, std::string& why);

// to_string(reason) with '-' for spaces ("protocol-error"), and back.
std::string close_reason_token(CloseReason reason);
std::optional<CloseReason> close_reason_from_token(std::string_view token);

// Splits at spaces outside double quotes (a backslash inside quotes escapes the next byte).
// An unterminated quote: std::nullopt.
std::optional<std::vector<std::string_view>> split_tokens(std::string_view line);

}  // namespace meter::protocol::detail
