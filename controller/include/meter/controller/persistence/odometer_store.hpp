// The odometer on disk: two copies written alternately, each atomic and CRC-checked, so that a
// kill, a power cut or a damaged file never loses or corrupts what was persisted and never lets
// the distance go backwards.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace meter::controller {

// One copy. 'sequence' increments per save across both copies; 'peer' is the sequence the other
// copy held when this one was written (0: none), so a copy put back from an older state is seen.
struct OdometerRecord {
  std::int64_t odo_um = 0, trip_um = 0;
  std::uint64_t sequence = 0;
  std::uint64_t peer = 0;
};

// What load() found.
enum class OdometerState : std::uint8_t {
  Fresh,     // nothing stored yet: start from 0
  Restored,  // record = the newest valid copy
  Refused,   // no copy can be trusted (both damaged, or a roll-back): the odometer is invalid and
             // nothing is written until reset() (meter-controller odometer-reset)
};
struct OdometerLoad {
  OdometerState state = OdometerState::Fresh;
  std::optional<OdometerRecord> record;
  std::vector<std::string> faults;  // one line per problem: "FILE: what is wrong"
};

// dir/odometer.a and dir/odometer.b, each written as: temp file, write, fsync, rename over the copy,
// fsync of the directory. A save writes the copy that does not hold the newest record, so the newest
// one is never touched while the next is written; a failed save leaves both copies as they were and
// the next save retries the same copy. dir/odometer.state (the single file of earlier versions) is
// loaded when neither copy exists, and removed once both copies have been written.
class OdometerStore {
 public:
  explicit OdometerStore(std::string dir);  // creates the directory if it can (a failure shows in load())
  // Reads both copies: the newest valid one is restored. Refused when none is valid although some
  // exist, or when the copies contradict each other (the newest says the other held a sequence it
  // does not hold, or holds more distance): a copy was put back from an older state.
  OdometerLoad load();
  // Writes the next copy (the store numbers it). Throws std::runtime_error naming the file and the
  // system error on any I/O failure, or when the store is refused; both copies stay as they were.
  std::uint64_t save(std::int64_t odo_um, std::int64_t trip_um);
  // The explicit reset of a refused store: both copies rewritten with this distance under a sequence
  // above every one on disk. Throws std::runtime_error on I/O failure.
  void reset(std::int64_t odo_um, std::int64_t trip_um);
  // The largest distance among the valid copies (or the old single file), nullopt when none is valid:
  // what the reset command restores unless told a distance.
  std::optional<OdometerRecord> best_valid() const;

  bool refused() const { return refused_; }
  std::string copy_path(int copy) const;  // copy 0 = odometer.a, 1 = odometer.b
  std::string legacy_path() const { return dir_ + "/odometer.state"; }

  static std::string format(const OdometerRecord& r);
  // Parses one copy; nullopt with *why set when it is damaged (empty, truncated, CRC, syntax).
  static std::optional<OdometerRecord> parse(const std::string& text, std::string* why);

 private:
  struct Copy {
    bool exists = false;
    std::optional<OdometerRecord> record;
    std::string why;
  };
  Copy read_copy(const std::string& path) const;
  void write_copy(int copy, const OdometerRecord& r);

  std::string dir_;
  std::string dir_error_;  // why the directory could not be created ("" = fine)
  bool refused_ = false;
  int next_ = 0;                       // the copy the next save writes
  std::uint64_t seq_ = 0;              // the newest sequence on disk
  std::uint64_t on_disk_[2] = {0, 0};  // the sequence each copy holds (0: none or damaged)
};

}  // namespace meter::controller
