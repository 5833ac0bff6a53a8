#include "meter/protocol/signal_table.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "meter/protocol/signal_change.hpp"

namespace meter::protocol {
SignalTable::SignalTable() : SignalTable(active_catalog()) {}

SignalTable::SignalTable(std::shared_ptr<const Catalog> catalog)
    : catalog_(std::move(catalog)), states_(catalog_->size()), changed_at_(catalog_->size(), 0) {}

std::size_t SignalTable::index_or_throw(SignalId id) const {
  const auto index = index_of(id);
  if (!index) throw std::out_of_range("signal id " + std::to_string(id) + " is not in the catalog");
  return *index;
}

const SignalState* SignalTable::find(SignalId id) const {
  const auto index = index_of(id);
  return index ? &states_[*index] : nullptr;
}

const SignalState& SignalTable::get(SignalId id) const { return states_[index_or_throw(id)]; }

std::uint64_t SignalTable::changed_at(SignalId id) const { return changed_at_[index_or_throw(id)]; }

bool SignalTable::set(SignalId id, SignalState state) {
  return store(index_or_throw(id), state.value, state.status, &state.text);
}

bool SignalTable::set(SignalId id, double value, SignalStatus status) {
  return store(index_or_throw(id), value, status, nullptr);
}

bool SignalTable::set_text(SignalId id, std::string text, SignalStatus status) {
  const std::size_t index = index_or_throw(id);
  return store(index, states_[index].value, status, &text);
}

bool SignalTable::store(std::size_t index, double value, SignalStatus status, std::string* text) {
  SignalState& s = states_[index];
  // The one change rule of both ends (signal_change.hpp): the value's bits, then the status.
  bool changed = signal_changed(s.value, s.status, value, status);
  s.value = value;
  s.status = status;
  if (text != nullptr && *text != s.text) {
    s.text = std::move(*text);
    changed = true;
  }
  if (changed) changed_at_[index] = ++version_;
  return changed;
}

}  // namespace meter::protocol
