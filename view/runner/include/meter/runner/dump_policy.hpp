// Which live frames are written as PNG (with their frames.csv row): every Nth frame
// (--dump-every), the first frame at or after each given time on the view's clock (--dump-at),
// the next frame after a request (SIGUSR1), and the final frame on exit (--dump-last). Pure, but for reading the options.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace meter::runner {

struct ViewOptions;

// Whether a frame is written, and whether anything beyond --dump-every asked for it (a --dump-at
// time or a request): such a dump is never dropped by a busy writer.
struct DumpChoice {
  bool write = false;
  bool asked = false;
};

class DumpPolicy {
 public:
  // every: 0 = none; at_times: seconds, any order; dump_last: write the final frame on exit.
  DumpPolicy(int every, std::vector<double> at_times, bool dump_last);

  // Frame `frame` (0-based) begins at `t` seconds; `requested`: a dump was asked for since the
  // previous frame. Times that fell due since the previous frame are used up: one dump covers
  // them all.
  DumpChoice decide(std::uint64_t frame, double t, bool requested);
  // After `frames_rendered` frames, whether the final one is written again on exit.
  bool dump_on_exit(std::uint64_t frames_rendered) const { return dump_last_ && frames_rendered > 0; }

 private:
  int every_;
  std::vector<double> at_;  // sorted
  std::size_t next_at_ = 0;
  bool dump_last_;
};

// The policy of --dump-every, --dump-at (parsed times) and --dump-last.
DumpPolicy dump_policy(const ViewOptions& options);
// The PNG file name of a dumped frame: frame_000123.png.
std::string png_name(std::uint64_t frame);

}  // namespace meter::runner
