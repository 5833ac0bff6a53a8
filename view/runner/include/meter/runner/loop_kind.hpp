// The live loop's kind (--pipeline, docs/pipeline.md): how its frames overlap, read from the
// options once, with the options that a kind cannot serve refused by name.
#pragma once

#include "meter/runner/view_options.hpp"

namespace meter::runner {

// sequential: frames on the --fps ticks, synchronous readback; concurrent: the PNG writer on its
// own thread, a frame as soon as a change may be drawn, each frame waited for; overlapped:
// concurrent, and a frame's GL work executes, fenced, while the next is taken in.
enum class LoopKind { Sequential, Concurrent, Overlapped };

// The kind --pipeline names. Throws ViewError for an unknown name, and for overlapped with
// --inject-fault (its fault schedule needs each frame completed before the next: concurrent or
// sequential, asked for by name).
LoopKind live_loop_kind(const ViewOptions& options);

}  // namespace meter::runner
