// The DBC parser's entry points: DBC text or a DBC file to a Database (database.hpp, which
// includes this header), leniently or (strict) refusing every quirk.
#pragma once

#include <string>
#include <string_view>

namespace meter::controller {

class Database;

struct DbcOptions {
  // Refuse every quirk: the first warning the lenient parse gives becomes a DbcError that lists
  // them all (file:line each). Without it, quirks are warnings and unreadable statements are skipped.
  bool strict = false;
};

// Parses DBC text (UTF-8, or cp1252 which is converted to UTF-8). Lenient: every tolerated problem
// is a warning in Database::warnings and never throws. With options.strict any warning throws.
Database parse_dbc(std::string_view text, const std::string& file = "<dbc>", const DbcOptions& options = {});
Database load_dbc(const std::string& path, const DbcOptions& options = {});  // DbcError also for unreadable files

}  // namespace meter::controller
