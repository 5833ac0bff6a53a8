#include <modbus.h>
#include <time.h>

#include <cerrno>
#include <cmath>
#include <stdexcept>
#include <thread>

#include "meter/controller/input/clocks.hpp"
#include "meter/controller/input/modbus_input.hpp"

namespace meter::controller {
namespace {
modbus_t* ctx(void* p) { return static_cast<modbus_t*>(p); }
}  // namespace

ModbusInput::ModbusInput(const std::string& target, const ModbusConfig& config) : target_(target), cfg_(config) {
  if (cfg_.registers.empty()) throw std::invalid_argument("modbus: the mapping defines no [modbus.register ...]");
  if (target.rfind("tcp:", 0) == 0) {
    std::string rest = target.substr(4);
    auto colon = rest.rfind(':');
    if (colon == std::string::npos) throw std::invalid_argument("modbus target: expected tcp:HOST:PORT, got '" + target + "'");
    std::string host = rest.substr(0, colon);
    int port = std::atoi(rest.c_str() + colon + 1);
    if (port <= 0 || port > 65535) throw std::invalid_argument("modbus target: bad port in '" + target + "'");
    ctx_ = modbus_new_tcp(host.c_str(), port);
  } else if (target.rfind("rtu:", 0) == 0) {
    // rtu:/dev/ttyUSB0:19200[:8N1]
    std::string rest = target.substr(4);
    auto c1 = rest.find(':');
    if (c1 == std::string::npos) throw std::invalid_argument("modbus target: expected rtu:DEVICE:BAUD[:8N1]");
    std::string dev = rest.substr(0, c1);
    std::string tail = rest.substr(c1 + 1);
    auto c2 = tail.find(':');
    int baud = std::atoi(tail.substr(0, c2).c_str());
    std::string fmt = c2 == std::string::npos ? "8N1" : tail.substr(c2 + 1);
    if (baud <= 0 || fmt.size() != 3 || (fmt[1] != 'N' && fmt[1] != 'E' && fmt[1] != 'O'))
      throw std::invalid_argument("modbus target: expected rtu:DEVICE:BAUD[:8N1|8E1|8O1], got '" + target + "'");
    ctx_ = modbus_new_rtu(dev.c_str(), baud, fmt[1], fmt[0] - '0', fmt[2] - '0');
    serial_ = true;
  } else {
    throw std::invalid_argument("modbus target: expected tcp:HOST:PORT or rtu:DEVICE:BAUD, got '" + target + "'");
  }
  if (!ctx_) throw std::runtime_error("modbus: cannot create a context for " + target + ": " + modbus_strerror(errno));
  modbus_set_slave(ctx(ctx_), cfg_.unit_id);
  double t = cfg_.response_timeout_s;
  const auto s = static_cast<std::uint32_t>(t), us = static_cast<std::uint32_t>((t - std::floor(t)) * 1e6);
  modbus_set_response_timeout(ctx(ctx_), s, us);
  modbus_set_byte_timeout(ctx(ctx_), s, us);  // a frame that stops half-way ends the read too
  for (const ModbusRegister& r : cfg_.registers) keys_.push_back(cfg_.source_key(r));
  next_poll_ = monotonic_ns();
}

ModbusInput::~ModbusInput() {
  if (ctx_) {
    modbus_close(ctx(ctx_));
    modbus_free(ctx(ctx_));
  }
}

std::int64_t ModbusInput::now_ns() const { return monotonic_ns(); }
std::string ModbusInput::describe() const { return "Modbus " + target_; }

BusHealth ModbusInput::health() const {
  BusHealth h;
  if (health_.state == ModbusLinkState::NotPolled) return h;
  h.polled_links = describe() + " " + std::string(to_string(health_.state));
  if (health_.state != ModbusLinkState::Ok) h.polled_links += " (" + health_.last_error + ")";
  return h;
}

void ModbusInput::invalidate_all(InputSink& sink, std::int64_t t) {
  for (const std::string& key : keys_) sink.on_value(key, 0.0, false, t);
}

void ModbusInput::fail(InputSink& sink, std::int64_t t, ModbusLinkState outcome, std::string error) {
  note_modbus_poll(health_, outcome, error);
  invalidate_all(sink, t);
}

void ModbusInput::poll_once(InputSink& sink) {
  const std::int64_t t = monotonic_ns();
  if (!connected_) {
    if (modbus_connect(ctx(ctx_)) != 0) return fail(sink, t, ModbusLinkState::Unreachable, std::string("connect: ") + modbus_strerror(errno));
    connected_ = true;
  }
  words_.assign(cfg_.registers.size(), {0, 0});
  for (std::size_t i = 0; i < cfg_.registers.size(); ++i) {
    const ModbusRegister& r = cfg_.registers[i];
    std::uint16_t* w = words_[i].data();
    int n = r.input_table ? modbus_read_input_registers(ctx(ctx_), r.address, r.words(), w)
                          : modbus_read_registers(ctx(ctx_), r.address, r.words(), w);
    if (n != r.words()) {
      // One bad poll invalidates the whole map, like a missing CAN frame.
      const int err = n < 0 ? errno : EMBBADDATA;
      const ModbusLinkState outcome = classify_modbus_read_error(err);
      std::string error = "read " + r.name + "@" + std::to_string(r.address) + ": " + modbus_strerror(err);
      if (outcome == ModbusLinkState::Unreachable || (outcome != ModbusLinkState::Exception && !serial_)) {
        modbus_close(ctx(ctx_));  // connection-level failure: reconnect next poll
        connected_ = false;
      } else if (serial_ && outcome != ModbusLinkState::Exception) {
        modbus_flush(ctx(ctx_));  // a serial line stays open: drop what is left of a bad or late answer
      }
      return fail(sink, t, outcome, std::move(error));
    }
  }
  if (!interpret_modbus_poll(cfg_, words_, heartbeat_, readings_))
    return fail(sink, t, ModbusLinkState::StaleHeartbeat,
                "heartbeat register '" + cfg_.heartbeat + "' stale for " + std::to_string(heartbeat_.same_polls) + " polls");
  note_modbus_poll(health_, ModbusLinkState::Ok);
  for (std::size_t i = 0; i < readings_.size(); ++i) sink.on_value(keys_[i], readings_[i].value, readings_[i].valid, t);
}

bool ModbusInput::poll(InputSink& sink, std::chrono::milliseconds timeout) {
  const std::int64_t now = monotonic_ns();
  if (now >= next_poll_) {
    poll_once(sink);
    const auto period = static_cast<std::int64_t>(cfg_.poll_s * 1e9);
    next_poll_ += period;
    if (next_poll_ < monotonic_ns()) next_poll_ = monotonic_ns() + period;  // fell behind: do not burst
    return true;
  }
  const std::int64_t wait = std::min<std::int64_t>(next_poll_ - now, std::chrono::duration_cast<std::chrono::nanoseconds>(timeout).count());
  if (wait > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(wait));
  return true;
}

}  // namespace meter::controller
