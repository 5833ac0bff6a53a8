// Fuzzes the odometer state files (--state-dir: odometer.a, odometer.b and the old single file
// odometer.state) as meter-controller reads them at start: the input is split at "\n--8<--\n"
// into the files' contents (an empty part: that file is absent), written to a private folder and
// loaded. What is restored must be one of the copies as parsed; a store that is not refused takes
// a save and a fresh store then restores exactly what was saved (nothing persisted is lost, the
// distance never goes backwards); a refused store writes nothing. A crash, a sanitizer report, an
// exception other than a refused save, or a broken invariant is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>

#include "meter/controller/persistence/odometer_store.hpp"

using namespace meter::controller;
namespace fs = std::filesystem;

namespace {

fs::path scratch_dir() {
  char tmpl[] = "/tmp/meter-fuzz-odometer-XXXXXX";
  const char* dir = ::mkdtemp(tmpl);
  if (dir == nullptr) std::abort();
  return dir;
}

bool same(const OdometerRecord& a, const OdometerRecord& b) {
  return a.odo_um == b.odo_um && a.trip_um == b.trip_um && a.sequence == b.sequence && a.peer == b.peer;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const fs::path dir = scratch_dir();
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::string cut = "\n--8<--\n";
  std::string parts[3];
  std::size_t at = 0;
  for (int i = 0; i < 3 && at <= text.size(); ++i) {
    const auto end = i < 2 ? text.find(cut, at) : std::string::npos;
    parts[i] = text.substr(at, end == std::string::npos ? std::string::npos : end - at);
    at = end == std::string::npos ? text.size() + 1 : end + cut.size();
  }
  const char* names[3] = {"odometer.a", "odometer.b", "odometer.state"};
  for (int i = 0; i < 3; ++i) {
    fs::remove(dir / names[i]);
    if (!parts[i].empty()) std::ofstream(dir / names[i], std::ios::binary) << parts[i];
  }
  OdometerStore store(dir.string());
  const OdometerLoad loaded = store.load();
  if (loaded.state == OdometerState::Restored) {
    if (!loaded.record || loaded.record->odo_um < 0 || loaded.record->trip_um < 0) std::abort();
    bool from_a_file = false;
    for (const auto& p : parts) {
      const auto parsed = OdometerStore::parse(p, nullptr);
      from_a_file = from_a_file || (parsed && same(*parsed, *loaded.record));
    }
    if (!from_a_file) std::abort();
    const auto again = OdometerStore::parse(OdometerStore::format(*loaded.record), nullptr);
    if (!again || !same(*again, *loaded.record)) std::abort();
  }
  if (loaded.state == OdometerState::Refused) {
    if (loaded.faults.empty()) std::abort();  // a refusal says why
    try {
      store.save(1, 1);
      std::abort();  // a refused store must not be written
    } catch (const std::runtime_error&) {
    }
    return 0;
  }
  const std::int64_t odo = loaded.record ? loaded.record->odo_um : 0;
  const std::int64_t next = odo < std::numeric_limits<std::int64_t>::max() ? odo + 1 : odo;
  store.save(next, 0);
  OdometerStore reopened(dir.string());
  const OdometerLoad after = reopened.load();
  if (after.state != OdometerState::Restored || !after.record || after.record->odo_um != next) std::abort();
  return 0;
}
