// meter-controller dump-dbc: a parsed DBC as JSON.
#pragma once

#include <iosfwd>
#include <string>

namespace meter::controller {

// dump-dbc: the parsed database as JSON (messages, signals with every field, value tables,
// warnings), for tools and the cross-check against other DBC parsers.
int dump_dbc_command(const std::string& dbc, std::ostream& out, std::ostream& err);

}  // namespace meter::controller
