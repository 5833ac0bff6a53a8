#include "link/handshake.hpp"

#include <algorithm>
#include <cstdio>

namespace meter::protocol::detail {
namespace {

std::string hex64(std::uint64_t v) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "0x%016llx", static_cast<unsigned long long>(v));
  return buf;
}

// Cuts at a UTF-8 boundary so the field stays valid text.
std::string clip_utf8(const std::string& text, std::size_t max_bytes) {
  if (text.size() <= max_bytes) return text;
  std::size_t end = max_bytes;
  while (end > 0 && (static_cast<unsigned char>(text[end]) & 0xC0U) == 0x80U) --end;
  return text.substr(0, end);
}

std::string describe(const Hello& h) {
  return (h.catalog_source.empty() ? std::string("(unnamed)") : h.catalog_source) + " (hash " +
         hex64(h.catalog_hash) + ", " + std::to_string(h.signal_count) + " signals)";
}

}  // namespace

Hello make_hello(Role role, const Catalog& catalog, std::uint64_t hash, const LinkOptions& options) {
  Hello hello;
  hello.role = role;
  hello.flags = role == Role::Subscriber && options.take_peer_catalog ? kHelloTakesCatalog : 0;
  hello.catalog_hash = hash;
  hello.signal_count = static_cast<std::uint16_t>(catalog.size());
  hello.heartbeat_period_ms = static_cast<std::uint32_t>(options.heartbeat_period.count());
  hello.name = clip_utf8(options.name, kMaxNameBytes);
  hello.catalog_source = clip_utf8(catalog.source(), kMaxTextBytes);
  return hello;
}

std::string check_hello(const Hello& hello, Role expected_role, CloseReason& reason) {
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
  return {};
}

CatalogAgreement agree_catalogs(std::uint64_t publisher_hash, std::uint64_t subscriber_hash, bool subscriber_takes) {
  if (publisher_hash == subscriber_hash) return CatalogAgreement::Same;
  return subscriber_takes ? CatalogAgreement::Transfer : CatalogAgreement::Refuse;
}

std::string catalog_mismatch(const Hello& publisher, const Hello& subscriber) {
  return "signal catalog mismatch: controller " + describe(publisher) + ", view " + describe(subscriber) +
         "; give both the same --catalog, or let the view take the controller's (--catalog-from-controller)";
}

std::vector<CatalogChunk> catalog_chunks(const Catalog& catalog, std::uint64_t hash) {
  const std::string& text = catalog.text();
  const std::size_t count = std::max<std::size_t>(1, (text.size() + kMaxCatalogChunkBytes - 1) / kMaxCatalogChunkBytes);
  std::vector<CatalogChunk> chunks;
  chunks.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    chunks.push_back(CatalogChunk{hash, static_cast<std::uint16_t>(i), static_cast<std::uint16_t>(count),
                                  text.substr(std::min(text.size(), i * kMaxCatalogChunkBytes), kMaxCatalogChunkBytes)});
  }
  return chunks;
}

CatalogAssembler::CatalogAssembler(std::uint64_t expected_hash, std::string origin)
    : expected_hash_(expected_hash), origin_(std::move(origin)) {}

std::string CatalogAssembler::add(const CatalogChunk& chunk) {
  if (complete_) return "CATALOG piece after the catalog was complete";
  if (chunk.catalog_hash != expected_hash_) {
    return "CATALOG piece for hash " + hex64(chunk.catalog_hash) + ", HELLO announced " + hex64(expected_hash_);
  }
  if (next_ == 0) count_ = chunk.count;
  if (chunk.index != next_ || chunk.count != count_) {
    return "CATALOG piece " + std::to_string(chunk.index) + " of " + std::to_string(chunk.count) + ", expected piece " +
           std::to_string(next_) + " of " + std::to_string(count_);
  }
  text_ += chunk.bytes;
  ++next_;
  if (next_ < count_) return {};
  auto parsed = parse_catalog(text_, origin_);
  if (!parsed.catalog) return "the controller's catalog does not load: " + parsed.error;
  if (parsed.catalog->hash() != expected_hash_) {
    return origin_ + " has hash " + hex64(parsed.catalog->hash()) + ", its HELLO announced " + hex64(expected_hash_);
  }
  catalog_ = std::move(parsed.catalog);
  complete_ = true;
  return {};
}

}  // namespace meter::protocol::detail
