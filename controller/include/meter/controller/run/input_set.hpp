// Several inputs in one controller (two CAN buses, CAN + Modbus) polled as one, on one clock.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "meter/controller/input/input.hpp"

namespace meter::controller {

// Several inputs polled as one, on the clock of the first (the time base): the others' timestamps
// are moved onto it by the difference of the two clocks, taken at every poll. Waits in one epoll on
// every member's Input::wait_fd() (woken by the first frame on any bus); inputs that pace
// themselves (a log replay, the Modbus poll period) are serviced without waiting on every wake-up.
class InputSet : public Input {
 public:
  struct Member {
    std::unique_ptr<Input> input;
    std::string name;  // what describe() calls it
    int tag = -1;  // input index written into its frames; -1: the frames carry their index already
  };
  explicit InputSet(std::vector<Member> members);
  ~InputSet() override;
  InputSet(const InputSet&) = delete;
  InputSet& operator=(const InputSet&) = delete;

  // False once the time base (the first input) has ended: a replayed log among live inputs ends
  // the run; live inputs never end.
  bool poll(InputSink& sink, std::chrono::milliseconds timeout) override;
  std::int64_t now_ns() const override { return members_.front().input->now_ns(); }
  std::string describe() const override;
  double rate() const override { return members_.front().input->rate(); }
  // The members' health folded into one: the worst bus state, every count summed (the stats line,
  // the trace and STATUS carry one health per controller).
  BusHealth health() const override;

 private:
  std::vector<Member> members_;
  std::vector<bool> ended_;
  int epoll_ = -1;
};

}  // namespace meter::controller
