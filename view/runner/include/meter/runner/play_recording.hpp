// --play RECORDING: renders a link recording (meter-controller run --record, meter-linkdump -o) on
// the view's own simulated clock instead of the wall clock. Frame k is drawn at t = k / fps
// seconds after the recording's first signal update, with every update stamped at or before that
// time applied; nothing waits, so a drive renders as fast as the machine allows and the same
// recording always gives the same frames. Dumps (--dump-every, --dump-at, --dump-last), frames.csv
// and the timing CSV are the live mode's; the clock is the recording's `sent` stamps.
#pragma once

#include <cstdint>
#include <ostream>
#include <vector>

#include "meter/protocol/recording.hpp"
#include "meter/runner/render_context.hpp"
#include "meter/runner/view_options.hpp"

namespace meter::runner {

// The frame times of a play: k / fps for k = 0.. while within `span_s` (the recording's last
// update minus its first, or --duration when given). At least one frame. Pure.
std::vector<double> play_frame_times(double fps, double span_s);

// The recording's span in seconds between its first and last SNAPSHOT/DELTA `sent` stamps, and the
// first stamp; throws ViewError naming the file when it holds no signal update.
struct PlaySpan {
  std::int64_t first_ns = 0;
  double span_s = 0.0;
};
PlaySpan play_span(const std::vector<protocol::RecordedFrame>& frames, const std::string& file);

// Reads the recording (its header must name this build's catalog), renders and dumps. Throws
// ViewError / RecordingError with the file and line of what is wrong.
void run_play(RenderContext& ctx, const ViewOptions& options, std::ostream& log);

}  // namespace meter::runner
