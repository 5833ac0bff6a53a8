#include "meter/controller/input/can_id_filter.hpp"

namespace meter::controller {

namespace {
constexpr std::uint32_t kSffMask = 0x7FFu;
constexpr std::uint32_t kEffMask = 0x1FFFFFFFu;
constexpr std::uint32_t kPdu2GroupMask = 0x03FFFF00u;  // EDP, DP, PF, PS
constexpr std::uint32_t kPdu1GroupMask = 0x03FF0000u;  // EDP, DP, PF (PS is a destination)
}  // namespace

CanIdFilter j1939_group_filter(std::uint32_t id29) {
  const std::uint32_t pf = (id29 >> 16) & 0xFFu;
  const std::uint32_t mask = pf < 240 ? kPdu1GroupMask : kPdu2GroupMask;
  return CanIdFilter{id29 & mask, true, mask};
}

std::uint32_t effective_mask(const CanIdFilter& f) {
  const std::uint32_t all = f.extended ? kEffMask : kSffMask;
  return f.mask == 0 ? all : (f.mask & all);
}

bool filters_accept(const std::vector<CanIdFilter>& filters, std::uint32_t id, bool extended) {
  if (filters.empty()) return true;
  for (const auto& f : filters) {
    const std::uint32_t m = effective_mask(f);
    if (f.extended == extended && (id & m) == (f.id & m)) return true;
  }
  return false;
}

}  // namespace meter::controller
