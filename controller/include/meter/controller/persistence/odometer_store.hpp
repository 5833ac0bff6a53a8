// The odometer record on disk, written so that a power cut or kill never loses or corrupts it.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace meter::controller {

// Atomic persistence of the odometer: write a temp file, fsync it, rename over the old one, fsync
// the directory. A kill at any instant leaves either the old or the new complete file. The record
// carries a CRC so a damaged file is detected instead of trusted.
struct OdometerRecord {
  std::int64_t odo_um = 0, trip_um = 0;
  std::uint64_t sequence = 0;  // increments per save
};
class OdometerStore {
 public:
  explicit OdometerStore(std::string dir);  // creates the directory if needed
  // nullopt when nothing was stored yet; throws std::runtime_error naming the file if it is corrupt.
  std::optional<OdometerRecord> load() const;
  void save(const OdometerRecord& r);  // throws std::runtime_error on I/O failure
  const std::string& path() const { return path_; }
  static std::string format(const OdometerRecord& r);
  static std::optional<OdometerRecord> parse(const std::string& text, std::string* why);

 private:
  std::string dir_, path_;
};

}  // namespace meter::controller
