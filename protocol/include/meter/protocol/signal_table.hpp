// The current state of every catalog signal, as plain data: what the Publisher sends and what the
// Subscriber has received, and what a consumer (the view's scene bindings) reads each frame.
//
// One SignalState per catalog entry, stored in catalog order; lookup by SignalId is O(1) through
// an index precomputed from the catalog. Every change that is observable (value bits, status or
// text) bumps the table's version and stamps the entry with it, so a consumer that remembers the
// version it last looked at can tell exactly which signals changed since (changed_at() > seen).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "meter/protocol/catalog.hpp"

namespace meter::protocol {

struct SignalState {
  double value = 0.0;
  SignalStatus status = SignalStatus::NotAvailable;
  std::string text;  // Text signals (and optional labels); at most kMaxTextBytes (wire.hpp)
  bool operator==(const SignalState&) const = default;
};

class SignalTable {
 public:
  // Every signal of `catalog` (default: the active catalog) at value 0, status NotAvailable, no
  // text; version() 0.
  SignalTable();
  explicit SignalTable(std::shared_ptr<const Catalog> catalog);

  const Catalog& catalog() const { return *catalog_; }
  const std::shared_ptr<const Catalog>& catalog_ptr() const { return catalog_; }
  // Position of `id` in catalog(), std::nullopt if the catalog has no such signal. O(1).
  std::optional<std::size_t> index_of(SignalId id) const { return catalog_->index_of(id); }

  std::size_t size() const { return states_.size(); }
  // All states in catalog order: states()[i] belongs to catalog().signals()[i].
  std::span<const SignalState> states() const { return states_; }

  const SignalState* find(SignalId id) const;  // nullptr for an id not in the catalog
  const SignalState& get(SignalId id) const;   // unknown id: std::out_of_range

  // Each setter stores the new state and returns true if anything observable changed: the value or
  // the status by signal_changed() (signal_change.hpp: the value's bits, so -0.0 after 0.0 is a
  // change), or the text.
  // A change bumps version() and stamps the entry with it. Unknown id: std::out_of_range.
  bool set(SignalId id, SignalState state);
  bool set(SignalId id, double value, SignalStatus status);          // keeps the text
  bool set_text(SignalId id, std::string text, SignalStatus status);  // keeps the value

  // Count of changes applied so far (every changed entry counts once per set call).
  std::uint64_t version() const { return version_; }
  // The version() right after `id` last changed; 0 if it never changed. Unknown id: std::out_of_range.
  std::uint64_t changed_at(SignalId id) const;

  // Equal when every signal holds an equal state; the change history (versions) is not compared.
  bool operator==(const SignalTable& other) const { return states_ == other.states_; }

 private:
  std::size_t index_or_throw(SignalId id) const;
  bool store(std::size_t index, double value, SignalStatus status, std::string* text);

  std::shared_ptr<const Catalog> catalog_;
  std::vector<SignalState> states_;
  std::vector<std::uint64_t> changed_at_;
  std::uint64_t version_ = 0;
};

}  // namespace meter::protocol
