#include "meter/controller/e2e/e2e_config.hpp"

namespace meter::controller {
namespace {
struct NamedChecksum {
  ChecksumKind kind;
  std::string_view name;
};
constexpr NamedChecksum kNames[] = {
    {ChecksumKind::None, "none"},
    {ChecksumKind::Toyota, "toyota"},
    {ChecksumKind::Honda, "honda"},
    {ChecksumKind::VwMqb, "vw-mqb"},
    {ChecksumKind::Hyundai, "hyundai"},
    {ChecksumKind::HyundaiCanFd, "hyundai-canfd"},
    {ChecksumKind::Subaru, "subaru"},
    {ChecksumKind::SubaruPreglobal, "subaru-preglobal"},
    {ChecksumKind::Chrysler, "chrysler"},
    {ChecksumKind::Nissan, "nissan"},
    {ChecksumKind::Mazda, "mazda"},
    {ChecksumKind::Tesla, "tesla"},
    {ChecksumKind::Profile01, "autosar-p01"},
    {ChecksumKind::Profile02, "autosar-p02"},
    {ChecksumKind::Profile05, "autosar-p05"},
    {ChecksumKind::Profile11, "autosar-p11"},
};
}  // namespace

std::string_view to_string(ChecksumKind kind) {
  for (const NamedChecksum& n : kNames)
    if (n.kind == kind) return n.name;
  return "unknown";
}

std::optional<ChecksumKind> checksum_kind_named(std::string_view name) {
  for (const NamedChecksum& n : kNames)
    if (n.name == name) return n.kind;
  return std::nullopt;
}

std::string checksum_kind_names() {
  std::string s;
  for (const NamedChecksum& n : kNames) s += (s.empty() ? "" : ", ") + std::string(n.name);
  return s;
}

}  // namespace meter::controller
