// The Catalog value type, its hash, and the process's active catalog.
#include "meter/protocol/catalog.hpp"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <fstream>
#include <limits>
#include <mutex>
#include <set>
#include <sstream>
#include <stdexcept>

namespace meter::protocol {
namespace {

constexpr std::uint16_t kNoEntry = std::numeric_limits<std::uint16_t>::max();

std::uint64_t hash_entries(std::span<const SignalInfo> entries) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  auto mix = [&h](std::string_view text) {
    for (unsigned char c : text) {
      h ^= c;
      h *= 0x100000001b3ULL;
    }
  };
  for (const auto& s : entries) {
    char numbers[96];
    // %.17g round-trips doubles exactly, so the text form is canonical.
    std::snprintf(numbers, sizeof numbers, "%u|%.17g|%.17g|%u", static_cast<unsigned>(s.id), s.min,
                  s.max, static_cast<unsigned>(s.kind));
    mix(numbers);
    mix("|");
    mix(s.name);
    mix("|");
    mix(s.unit);
    mix("\n");
  }
  return h;
}

// Every catalog ever made active stays alive: catalog() and find_signal() hand out spans and
// pointers into it, and replacing the active one (a view adopting its controller's catalog) must
// not leave those dangling. A process installs a handful at most. `current` lets the shorthands
// (the decoder checks every entry's id with one) read it with one atomic load, no lock.
struct ActiveCatalogs {
  std::mutex mutex;
  std::shared_ptr<const Catalog> active;
  std::vector<std::shared_ptr<const Catalog>> retired;
  std::atomic<const Catalog*> current{nullptr};
};

ActiveCatalogs& actives() {
  static ActiveCatalogs a;
  return a;
}

const Catalog& active_ref() {
  auto& a = actives();
  if (const Catalog* c = a.current.load(std::memory_order_acquire)) return *c;
  return *active_catalog();  // first use: installs the default; it stays alive in `active`
}

}  // namespace

Catalog::Catalog(std::vector<SignalInfo> signals, std::string source, std::string text)
    : signals_(std::move(signals)), source_(std::move(source)), text_(std::move(text)) {
  std::sort(signals_.begin(), signals_.end(), [](const SignalInfo& a, const SignalInfo& b) { return a.id < b.id; });
  if (signals_.size() >= kNoEntry) throw std::invalid_argument(source_ + ": too many signals");
  SignalId max_id = 0;
  for (std::size_t i = 0; i < signals_.size(); ++i) {
    if (i > 0 && signals_[i].id == signals_[i - 1].id) {
      throw std::invalid_argument(source_ + ": signal id " + std::to_string(signals_[i].id) + " is used by both " +
                                  signals_[i - 1].name + " and " + signals_[i].name);
    }
    max_id = std::max(max_id, signals_[i].id);
  }
  std::set<std::string_view> names;
  for (const auto& s : signals_) {
    if (!names.insert(s.name).second) throw std::invalid_argument(source_ + ": signal name " + s.name + " appears twice");
  }
  position_by_id_.assign(signals_.empty() ? 0 : static_cast<std::size_t>(max_id) + 1, kNoEntry);
  for (std::size_t i = 0; i < signals_.size(); ++i) position_by_id_[signals_[i].id] = static_cast<std::uint16_t>(i);
  hash_ = hash_entries(signals_);
}

std::optional<std::size_t> Catalog::index_of(SignalId id) const {
  if (id >= position_by_id_.size() || position_by_id_[id] == kNoEntry) return std::nullopt;
  return position_by_id_[id];
}

const SignalInfo* Catalog::find(SignalId id) const {
  const auto index = index_of(id);
  return index ? &signals_[*index] : nullptr;
}

const SignalInfo* Catalog::find(std::string_view name) const {
  for (const auto& s : signals_) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

const SignalInfo& Catalog::require(std::string_view name, std::string_view needed_for) const {
  if (const auto* s = find(name)) return *s;
  throw std::runtime_error("signal catalog " + source_ + " has no signal " + std::string(name) + " (needed for " +
                           std::string(needed_for) + ")");
}

std::shared_ptr<const Catalog> load_catalog_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open signal catalog " + path);
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw std::runtime_error("cannot read signal catalog " + path);
  auto result = parse_catalog(ss.str(), path);
  if (!result.catalog) throw std::runtime_error(result.error);
  return result.catalog;
}

std::shared_ptr<const Catalog> active_catalog() {
  auto& a = actives();
  std::lock_guard lock(a.mutex);
  if (!a.active) {
    a.active = default_catalog();
    a.current.store(a.active.get(), std::memory_order_release);
  }
  return a.active;
}

void set_active_catalog(std::shared_ptr<const Catalog> catalog) {
  if (!catalog) throw std::invalid_argument("set_active_catalog: null catalog");
  auto& a = actives();
  std::lock_guard lock(a.mutex);
  if (a.active) a.retired.push_back(std::move(a.active));
  a.active = std::move(catalog);
  a.current.store(a.active.get(), std::memory_order_release);
}

std::shared_ptr<const Catalog> use_catalog_option(const std::string& path) {
  if (!path.empty()) set_active_catalog(load_catalog_file(path));
  return active_catalog();
}

std::span<const SignalInfo> catalog() { return active_ref().signals(); }
const SignalInfo* find_signal(SignalId id) { return active_ref().find(id); }
const SignalInfo* find_signal(std::string_view name) { return active_ref().find(name); }
std::uint64_t catalog_hash() { return active_ref().hash(); }

std::string_view to_string(SignalKind kind) {
  switch (kind) {
    case SignalKind::Gauge: return "gauge";
    case SignalKind::Enum: return "enum";
    case SignalKind::Telltale: return "telltale";
    case SignalKind::Counter: return "counter";
    case SignalKind::Text: return "text";
  }
  return "unknown";
}

std::optional<SignalKind> kind_from_string(std::string_view text) {
  for (auto k : {SignalKind::Gauge, SignalKind::Enum, SignalKind::Telltale, SignalKind::Counter, SignalKind::Text}) {
    if (to_string(k) == text) return k;
  }
  return std::nullopt;
}

std::string_view to_string(SignalStatus status) {
  switch (status) {
    case SignalStatus::Valid: return "valid";
    case SignalStatus::TimedOut: return "timed-out";
    case SignalStatus::Invalid: return "invalid";
    case SignalStatus::NotAvailable: return "not-available";
  }
  return "unknown";
}

std::optional<SignalStatus> status_from_string(std::string_view text) {
  for (auto s : {SignalStatus::Valid, SignalStatus::TimedOut, SignalStatus::Invalid,
                 SignalStatus::NotAvailable}) {
    if (to_string(s) == text) return s;
  }
  return std::nullopt;
}

}  // namespace meter::protocol
