// DBC files come as UTF-8 or as Windows-1252 (CANdb++ on Windows): the parser works on UTF-8.
#pragma once

#include <string>
#include <string_view>

namespace meter::controller::dbc_parse {

// The offset of the first byte that does not start a valid UTF-8 sequence, or npos.
std::size_t first_invalid_utf8(std::string_view s);
bool valid_utf8(std::string_view s);
// Windows-1252 to UTF-8 (0x80..0x9F differ from Latin-1; undefined bytes become U+FFFD).
std::string cp1252_to_utf8(std::string_view s);

}  // namespace meter::controller::dbc_parse
