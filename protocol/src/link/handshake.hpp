// The HELLO exchange that opens every connection: what this end announces, the check of what the
// peer announced (protocol version, role), and the signal-catalog agreement: equal hashes, or the
// publisher sends its catalog to a subscriber that takes it (CATALOG pieces), or a refusal naming
// both catalog files.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "meter/protocol/catalog.hpp"
#include "meter/protocol/link.hpp"
#include "meter/protocol/wire.hpp"

namespace meter::protocol::detail {

// The HELLO this end sends: its role, catalog hash (`hash`, normally catalog.hash()), signal
// count, catalog file, heartbeat period and name; a subscriber sets kHelloTakesCatalog when its
// options let it take the publisher's catalog.
Hello make_hello(Role role, const Catalog& catalog, std::uint64_t hash, const LinkOptions& options);

// Checks a received HELLO's version and role; "" if acceptable, else the refusal text.
std::string check_hello(const Hello& hello, Role expected_role, CloseReason& reason);

// What to do about the two catalogs once the HELLOs are acceptable.
enum class CatalogAgreement { Same, Transfer, Refuse };
CatalogAgreement agree_catalogs(std::uint64_t publisher_hash, std::uint64_t subscriber_hash, bool subscriber_takes);

// The refusal text for different catalogs; names both files (the controller's and the view's).
std::string catalog_mismatch(const Hello& publisher, const Hello& subscriber);

// The publisher's catalog as CATALOG pieces, each at most kMaxCatalogChunkBytes.
std::vector<CatalogChunk> catalog_chunks(const Catalog& catalog, std::uint64_t hash);

// Collects CATALOG pieces on the subscriber side. add() returns "" while all is well, else the
// refusal text; once complete() the pieces are parsed into a catalog (take()).
class CatalogAssembler {
 public:
  CatalogAssembler(std::uint64_t expected_hash, std::string origin);
  std::string add(const CatalogChunk& chunk);
  bool complete() const { return complete_; }
  std::shared_ptr<const Catalog> take() { return std::move(catalog_); }

 private:
  std::uint64_t expected_hash_;
  std::string origin_;  // names the catalog in errors: "catalog sent by meter-controller (FILE)"
  std::string text_;
  std::uint16_t next_ = 0;
  std::uint16_t count_ = 0;
  bool complete_ = false;
  std::shared_ptr<const Catalog> catalog_;
};

}  // namespace meter::protocol::detail
