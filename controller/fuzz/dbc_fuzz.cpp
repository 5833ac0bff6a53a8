// Fuzzes the DBC parser the way meter-controller uses a DBC: parse the text, then look every
// message up by id and decode a payload (taken from the input's bytes) at every length from empty
// to the message's size. A parse error must be a DbcError; a decoded value must be finite unless
// its status says NotFinite, and every signal index must point into its message.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <span>
#include <vector>

#include "fixed_vehicle.hpp"
#include "meter/controller/dbc/codec.hpp"
#include "meter/controller/dbc/database.hpp"

using namespace meter::controller;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Database db;
  try {
    db = parse_dbc(fuzz::as_text(data, size), "fuzz.dbc");
  } catch (const DbcError&) {
    return 0;
  }
  std::array<std::uint8_t, 64> payload{};
  for (std::size_t i = 0; i < payload.size() && size > 0; ++i) payload[i] = data[(i * 7919) % size];
  std::vector<DecodedSignal> decoded;
  for (const DbcMessage& m : db.messages) {
    if (!db.find(m.id, m.extended)) std::abort();  // every parsed message is found by its own id
    for (std::size_t len : {std::size_t{0}, std::size_t{m.size} / 2, std::size_t{m.size}, payload.size()}) {
      decode(m, std::span<const std::uint8_t>(payload.data(), std::min(len, payload.size())), decoded);
      for (const DecodedSignal& d : decoded) {
        if (d.signal < 0 || static_cast<std::size_t>(d.signal) >= m.signals.size()) std::abort();
        if (d.status != DecodeStatus::NotFinite && !std::isfinite(d.physical)) std::abort();
        (void)signal_of(m, d).choice(d.raw_signed());
      }
    }
  }
  return 0;
}
