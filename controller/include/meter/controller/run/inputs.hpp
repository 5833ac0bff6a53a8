// Several inputs in one controller (two CAN buses, CAN + Modbus): which --input goes with which
// --dbc, the candump logs merged onto one timeline, and the set that polls every input on one clock.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "meter/controller/input/candump_log.hpp"
#include "meter/controller/input/input.hpp"

namespace meter::controller {

enum class InputKind : std::uint8_t { Log, SocketCan, Modbus };

// One --input and its DBC.
struct InputSpec {
  std::string name;    // empty: the only input, unnamed
  std::string target;  // log:FILE | can:IFACE | modbus-tcp:HOST:PORT | modbus-rtu:DEV:BAUD[:8N1]
  std::string dbc;     // empty: none
  InputKind kind = InputKind::Log;
};

// The kind of an --input target; throws std::invalid_argument naming the accepted forms.
InputKind input_kind(const std::string& target);

// Pairs every --input [NAME=]TARGET with its --dbc [NAME=]FILE. One input needs no name (and takes
// an unnamed --dbc); with several, each input has a distinct name and each --dbc names its input.
// Throws std::invalid_argument naming the option and what was expected: a missing, repeated or
// reserved name, a --dbc for no input or a second one for the same input, a CAN input among
// several without a DBC, a DBC on a Modbus input among several, more than one Modbus input.
std::vector<InputSpec> parse_input_specs(const std::vector<std::string>& inputs, const std::vector<std::string>& dbcs);

// Several candump logs as one: every frame tagged with its log's input index (the first of each
// pair), all frames in timestamp order, each file's own order kept where its timestamps tie or
// step back. The logs were recorded on one clock, so their relative timing is kept exactly.
ParsedLog merge_logs(std::vector<std::pair<int, ParsedLog>> logs);

// Several inputs polled as one, on the clock of the first (the time base): the others' timestamps
// are moved onto it by the difference of the two clocks, taken at every poll. Waits in one epoll on
// every SocketCAN socket (woken by the first frame on any bus); inputs that pace themselves (a log
// replay, the Modbus poll period) are serviced without waiting on every wake-up.
class InputSet : public Input {
 public:
  struct Member {
    std::unique_ptr<Input> input;
    std::string name;  // what describe() calls it
    int tag = -1;  // input index written into its frames; -1: the frames carry their index already
    int fd = -1;   // readable when frames wait (SocketCAN); -1: the input paces itself
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
