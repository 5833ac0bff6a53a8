#include "meter/protocol/signal_table.hpp"

#include <algorithm>
#include <bit>
#include <limits>
#include <stdexcept>
#include <utility>

namespace meter::protocol {
namespace {

constexpr std::uint16_t kNoEntry = std::numeric_limits<std::uint16_t>::max();

// id -> catalog position, one slot per id up to the largest id in the catalog.
const std::vector<std::uint16_t>& position_by_id() {
  static const std::vector<std::uint16_t> index = [] {
    const auto entries = catalog();
    SignalId max_id = 0;
    for (const auto& s : entries) max_id = std::max(max_id, s.id);
    std::vector<std::uint16_t> by_id(static_cast<std::size_t>(max_id) + 1, kNoEntry);
    for (std::size_t i = 0; i < entries.size(); ++i) by_id[entries[i].id] = static_cast<std::uint16_t>(i);
    return by_id;
  }();
  return index;
}

}  // namespace

SignalTable::SignalTable() : states_(catalog().size()), changed_at_(catalog().size(), 0) {}

std::optional<std::size_t> SignalTable::index_of(SignalId id) {
  const auto& by_id = position_by_id();
  if (id >= by_id.size() || by_id[id] == kNoEntry) return std::nullopt;
  return by_id[id];
}

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
  // Compare bits, not values: -0.0 vs 0.0 is a change a display may care about, and it keeps the
  // comparison exact.
  bool changed = std::bit_cast<std::uint64_t>(s.value) != std::bit_cast<std::uint64_t>(value) || s.status != status;
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
