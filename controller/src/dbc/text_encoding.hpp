// DBC files come as UTF-8 or as Windows-1252 (CANdb++ on Windows): the parser works on UTF-8.
#pragma once

#include <string>
#include <string_view>

namespace meter::controller::dbc_parse {

bool valid_utf8(std::string_view s);
// Windows-1252 to UTF-8 (0x80..0x9F differ from Latin-1; undefined bytes become U+FFFD).
std::string cp1252_to_utf8(std::string_view s);

}  // namespace meter::controller::dbc_parse
