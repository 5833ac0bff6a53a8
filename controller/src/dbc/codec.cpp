// DBC decoder and encoder: bit extraction for Intel and Motorola signals up to 64 bits, sign
// extension, IEEE float/double, multiplexing, J1939 'not available' patterns.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "bit_layout.hpp"
#include "meter/controller/dbc/codec.hpp"

namespace meter::controller {
namespace {

using dbc_layout::bit_location;
using dbc_layout::mask_bits;
using dbc_layout::motorola_msb_linear;

inline std::uint64_t load_le64(const std::uint8_t* p) {
  std::uint64_t v;
  std::memcpy(&v, p, 8);
  if constexpr (std::endian::native == std::endian::big) v = __builtin_bswap64(v);
  return v;
}
inline std::uint64_t load_be64(const std::uint8_t* p) {
  std::uint64_t v;
  std::memcpy(&v, p, 8);
  if constexpr (std::endian::native == std::endian::little) v = __builtin_bswap64(v);
  return v;
}

// Raw extraction from a zero-padded buffer of at least 72 bytes.
std::uint64_t extract_padded(const DbcSignal& s, const std::uint8_t* buf) {
  const unsigned len = s.length;
  std::uint64_t raw;
  if (s.little_endian) {
    unsigned byte0 = s.start_bit / 8, shift = s.start_bit % 8;
    if (shift + len <= 64) {
      raw = (load_le64(buf + byte0) >> shift) & mask_bits(len);
    } else {
      raw = (load_le64(buf + byte0) >> shift) | (static_cast<std::uint64_t>(buf[byte0 + 8]) << (64 - shift));
      raw &= mask_bits(len);
    }
  } else {
    unsigned msb = motorola_msb_linear(s.start_bit);
    unsigned byte0 = msb / 8, off = msb % 8;
    if (off + len <= 64) {
      raw = (load_be64(buf + byte0) << off) >> (64 - len);
    } else {
      raw = 0;
      for (unsigned i = 0; i < len; ++i) {
        unsigned by, bi;
        bit_location(s, i, by, bi);
        raw |= static_cast<std::uint64_t>((buf[by] >> bi) & 1u) << i;
      }
    }
  }
  if (s.is_signed && s.value_type == ValueType::Integer && len < 64 && (raw >> (len - 1)) & 1u)
    raw |= ~mask_bits(len);
  return raw;
}

DecodeStatus j1939_status(const DbcSignal& s, std::uint64_t raw) {
  if (s.is_signed || s.value_type != ValueType::Integer) return DecodeStatus::Valid;
  switch (s.length) {
    case 2: return raw == 3 ? DecodeStatus::NotAvailable : raw == 2 ? DecodeStatus::ErrorValue : DecodeStatus::Valid;
    case 4: return raw == 0xF ? DecodeStatus::NotAvailable : raw == 0xE ? DecodeStatus::ErrorValue : DecodeStatus::Valid;
    case 8: return raw == 0xFF ? DecodeStatus::NotAvailable : raw == 0xFE ? DecodeStatus::ErrorValue : DecodeStatus::Valid;
    case 16: return raw >= 0xFF00 ? DecodeStatus::NotAvailable : raw >= 0xFE00 ? DecodeStatus::ErrorValue : DecodeStatus::Valid;
    case 32: return raw >= 0xFF000000u ? DecodeStatus::NotAvailable : raw >= 0xFE000000u ? DecodeStatus::ErrorValue : DecodeStatus::Valid;
    default: return DecodeStatus::Valid;
  }
}

bool in_ranges(const DbcSignal& s, std::uint64_t v) {
  for (const auto& r : s.mux_ranges)
    if (v >= r.lo && v <= r.hi) return true;
  return false;
}

}  // namespace

std::string_view to_string(DecodeStatus s) {
  switch (s) {
    case DecodeStatus::Valid: return "valid";
    case DecodeStatus::ShortFrame: return "short_frame";
    case DecodeStatus::OutOfRange: return "out_of_range";
    case DecodeStatus::NotAvailable: return "not_available";
    case DecodeStatus::ErrorValue: return "error_value";
    case DecodeStatus::NotFinite: return "not_finite";
  }
  return "?";
}

std::uint64_t extract_raw(const DbcSignal& s, std::span<const std::uint8_t> payload) {
  std::uint8_t buf[80] = {};
  std::memcpy(buf, payload.data(), std::min<std::size_t>(payload.size(), 64));
  return extract_padded(s, buf);
}

void insert_raw(const DbcSignal& s, std::uint64_t raw, std::span<std::uint8_t> payload) {
  for (unsigned i = 0; i < s.length; ++i) {
    unsigned by, bi;
    bit_location(s, i, by, bi);
    if (by >= payload.size()) throw std::out_of_range("signal " + s.name + " does not fit the payload");
    std::uint8_t m = static_cast<std::uint8_t>(1u << bi);
    if ((raw >> i) & 1u) payload[by] |= m;
    else payload[by] &= static_cast<std::uint8_t>(~m);
  }
}

double raw_to_physical(const DbcSignal& s, std::uint64_t raw) {
  double v;
  switch (s.value_type) {
    case ValueType::Float32: v = std::bit_cast<float>(static_cast<std::uint32_t>(raw)); break;
    case ValueType::Float64: v = std::bit_cast<double>(raw); break;
    default: v = s.is_signed ? static_cast<double>(static_cast<std::int64_t>(raw)) : static_cast<double>(raw);
  }
  return v * s.factor + s.offset;
}

std::size_t decode(const DbcMessage& m, std::span<const std::uint8_t> payload, std::vector<DecodedSignal>& out) {
  out.clear();
  std::uint8_t buf[80] = {};
  const std::size_t n = std::min<std::size_t>(payload.size(), 64);
  std::memcpy(buf, payload.data(), n);
  const std::size_t count = m.signals.size();
  // Multiplexor raws, computed on demand (a switch may itself be multiplexed: mNM).
  constexpr int kUnknown = 0, kActive = 1, kInactive = 2;
  int state_small[64];
  std::vector<int> state_big;
  int* state = state_small;
  if (count > 64) {
    state_big.assign(count, kUnknown);
    state = state_big.data();
  } else {
    std::fill(state_small, state_small + count, kUnknown);
  }
  auto active = [&](auto& self, std::size_t i, int depth) -> bool {
    if (state[i] != kUnknown) return state[i] == kActive;
    const DbcSignal& s = m.signals[i];
    bool a = true;
    if (s.mux_switch >= 0) {
      auto sw = static_cast<std::size_t>(s.mux_switch);
      const DbcSignal& w = m.signals[sw];
      a = depth < 16 && w.bytes_needed() <= n && self(self, sw, depth + 1) && in_ranges(s, extract_padded(w, buf));
    }
    state[i] = a ? kActive : kInactive;
    return a;
  };
  for (std::size_t i = 0; i < count; ++i) {
    const DbcSignal& s = m.signals[i];
    if (s.mux_switch >= 0 && !active(active, i, 0)) continue;
    DecodedSignal d;
    d.signal = static_cast<int>(i);
    d.raw = extract_padded(s, buf);
    d.physical = raw_to_physical(s, d.raw);
    if (s.bytes_needed() > n) {
      d.status = DecodeStatus::ShortFrame;
      if (!std::isfinite(d.physical)) d.physical = 0.0;  // the zero padding times a huge factor
    } else if (!std::isfinite(d.physical)) {
      d.status = DecodeStatus::NotFinite;
      d.physical = 0.0;
    } else if (m.j1939 && (d.status = j1939_status(s, d.raw)) != DecodeStatus::Valid) {
      // keep the J1939 status
    } else if (s.has_range()) {
      double tol = 1e-9 * std::max({1.0, std::fabs(s.minimum), std::fabs(s.maximum)});
      if (d.physical < s.minimum - tol || d.physical > s.maximum + tol) d.status = DecodeStatus::OutOfRange;
    }
    out.push_back(d);
  }
  return out.size();
}

const DecodedSignal* find_decoded(const DbcMessage& m, std::span<const DecodedSignal> decoded, std::string_view name) {
  for (const auto& d : decoded)
    if (signal_of(m, d).name == name) return &d;
  return nullptr;
}

std::uint64_t physical_to_raw(const DbcSignal& s, double physical) {
  if (!std::isfinite(physical)) throw std::invalid_argument("signal " + s.name + ": value is not finite");
  double scaled = (physical - s.offset) / s.factor;
  // A zero factor (or a huge value over a tiny factor) gives a non-finite raw; converting that to an
  // integer or a float is undefined behaviour, so it is refused like any other value that does not fit.
  if (!std::isfinite(scaled))
    throw std::out_of_range("signal " + s.name + ": " + std::to_string(physical) + " gives raw " + std::to_string(scaled) +
                            " with factor " + std::to_string(s.factor) + " and offset " + std::to_string(s.offset));
  if (s.value_type == ValueType::Float32) {
    if (std::fabs(scaled) > static_cast<double>(std::numeric_limits<float>::max()))
      throw std::out_of_range("signal " + s.name + ": raw " + std::to_string(scaled) + " does not fit a 32-bit float");
    return std::bit_cast<std::uint32_t>(static_cast<float>(scaled));
  }
  if (s.value_type == ValueType::Float64) return std::bit_cast<std::uint64_t>(scaled);
  double r = std::nearbyint(scaled);
  // Bounds as exact powers of two, upper one exclusive: 2^63 - 1 and 2^64 - 1 are not doubles (they
  // round up to 2^63 / 2^64), so an inclusive "hi = 2^n - 1" let r = 2^63 through to an undefined
  // int64 conversion and silently saturated 2^64.
  const double lo = s.is_signed ? -std::ldexp(1.0, s.length - 1) : 0.0;
  const double hi_excl = s.is_signed ? std::ldexp(1.0, s.length - 1) : std::ldexp(1.0, s.length);
  if (r < lo || r >= hi_excl)
    throw std::out_of_range("signal " + s.name + ": " + std::to_string(physical) + " needs raw " + std::to_string(r) +
                            ", outside the " + std::to_string(s.length) + "-bit range");
  const std::uint64_t raw = s.is_signed ? static_cast<std::uint64_t>(static_cast<std::int64_t>(r)) : static_cast<std::uint64_t>(r);
  return raw & mask_bits(s.length);
}

std::vector<std::uint8_t> encode(const DbcMessage& m, std::span<const std::pair<std::string_view, double>> values) {
  std::vector<std::uint8_t> payload(m.size, 0);
  std::vector<int> idx;
  idx.reserve(values.size());
  for (const auto& [name, v] : values) {
    int i = m.find_signal(name);
    if (i < 0) throw std::invalid_argument("message " + m.name + " has no signal '" + std::string(name) + "'");
    idx.push_back(i);
  }
  // Multiplexors first so the multiplexed signals can be checked against them.
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t k = 0; k < values.size(); ++k) {
      const DbcSignal& s = m.signals[static_cast<std::size_t>(idx[k])];
      bool is_switch = s.is_multiplexor;
      if ((pass == 0) != is_switch) continue;
      if (s.mux_switch >= 0) {
        const DbcSignal& w = m.signals[static_cast<std::size_t>(s.mux_switch)];
        if (!in_ranges(s, extract_raw(w, payload)))
          throw std::invalid_argument("signal " + m.name + "." + s.name + " is not selected by the multiplexor value given for " + w.name);
      }
      insert_raw(s, physical_to_raw(s, values[k].second), payload);
    }
  }
  return payload;
}

}  // namespace meter::controller
