// meter-controller decode --e2e: a recorded CAN log checked end to end, to verify a vehicle's E2E
// configuration before it is trusted on the road.
#pragma once

#include <iosfwd>
#include <string>

namespace meter::controller {

// Every frame of a protected message checked (checksum, counter) as the running controller would:
// one CSV row per checked frame on out ("timestamp,message,checksum,received,expected,counter,
// counter_status,used"); on err what is checked and why (the map's [e2e] sections, or without a
// map the make and algorithm the DBC's conventions identify, or that none was found) and a summary
// per message, naming each likely configuration mismatch. Returns 0, 2 when some message is a
// likely mismatch, 1 on an error.
int decode_e2e_command(const std::string& dbc, const std::string& log, const std::string& map, std::ostream& out,
                       std::ostream& err, bool strict = false);

}  // namespace meter::controller
