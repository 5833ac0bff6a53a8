// The HELLO exchange that opens every connection: what this end announces, and the check of what
// the peer announced (protocol version, role, signal catalog hash).
#pragma once

#include <cstdint>
#include <string>

#include "meter/protocol/link.hpp"
#include "meter/protocol/wire.hpp"

namespace meter::protocol::detail {

// The HELLO this end sends: its role, catalog hash, heartbeat period and name.
Hello make_hello(Role role, std::uint64_t catalog_hash, const LinkOptions& options);

// Checks a received HELLO against this build; "" if acceptable, else the refusal text.
std::string check_hello(const Hello& hello, Role expected_role, std::uint64_t our_hash, CloseReason& reason);

}  // namespace meter::protocol::detail
