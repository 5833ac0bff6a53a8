#include "link/handshake.hpp"

#include <cstdio>

namespace meter::protocol::detail {
namespace {

std::string hex64(std::uint64_t v) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "0x%016llx", static_cast<unsigned long long>(v));
  return buf;
}

}  // namespace

Hello make_hello(Role role, std::uint64_t catalog_hash, const LinkOptions& options) {
  Hello hello;
  hello.role = role;
  hello.catalog_hash = catalog_hash;
  hello.signal_count = static_cast<std::uint16_t>(catalog().size());
  hello.heartbeat_period_ms = static_cast<std::uint32_t>(options.heartbeat_period.count());
  hello.name = options.name.substr(0, kMaxNameBytes);
  return hello;
}

std::string check_hello(const Hello& hello, Role expected_role, std::uint64_t our_hash, CloseReason& reason) {
  if (hello.protocol_version != kProtocolVersion) {
    reason = CloseReason::VersionMismatch;
    return "peer speaks protocol version " + std::to_string(hello.protocol_version) + ", this build speaks " +
           std::to_string(kProtocolVersion);
  }
  if (hello.role != expected_role) {
    reason = CloseReason::RoleMismatch;
    return "peer says it is a " + std::string(to_string(hello.role)) + ", expected a " +
           std::string(to_string(expected_role));
  }
  if (hello.catalog_hash != our_hash) {
    reason = CloseReason::CatalogMismatch;
    return "signal catalog mismatch: peer catalog hash " + hex64(hello.catalog_hash) + " (" +
           std::to_string(hello.signal_count) + " signals), ours " + hex64(our_hash) + " (" +
           std::to_string(catalog().size()) + " signals); rebuild controller and view from the same protocol/ catalog";
  }
  return {};
}

}  // namespace meter::protocol::detail
