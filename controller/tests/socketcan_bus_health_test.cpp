// The bus state as Linux CAN error frames report it (linux/can/error.h): warning, error-passive,
// bus-off and the way back; the class counters; remote frames counted, data frames ignored.
#include <linux/can/error.h>

#include <gtest/gtest.h>

#include "meter/controller/input/bus_health.hpp"
#include "meter/controller/input/can_frame.hpp"

namespace meter::controller {
namespace {

CanFrame error_frame(std::uint32_t cls, std::uint8_t ctrl = 0, std::uint8_t tx = 0, std::uint8_t rx = 0) {
  CanFrame f;
  f.error = true;
  f.id = cls;
  f.len = 8;
  f.data[1] = ctrl;
  f.data[6] = tx;
  f.data[7] = rx;
  return f;
}

TEST(BusHealth, ErrorFramesDriveTheState) {
  BusHealth h;
  EXPECT_EQ(h.state, BusState::ErrorActive);
  note_frame(h, error_frame(CAN_ERR_CRTL | CAN_ERR_CNT, CAN_ERR_CRTL_TX_WARNING, 97, 0));
  EXPECT_EQ(h.state, BusState::ErrorWarning);
  EXPECT_EQ(h.tx_errors, 97);
  note_frame(h, error_frame(CAN_ERR_CRTL | CAN_ERR_CNT, CAN_ERR_CRTL_RX_PASSIVE, 100, 128));
  EXPECT_EQ(h.state, BusState::ErrorPassive);
  EXPECT_EQ(h.rx_errors, 128);
  note_frame(h, error_frame(CAN_ERR_BUSOFF));
  note_frame(h, error_frame(CAN_ERR_BUSOFF));
  EXPECT_EQ(h.state, BusState::BusOff);
  EXPECT_EQ(h.bus_off_events, 1U) << "still bus-off: one event";
  note_frame(h, error_frame(CAN_ERR_RESTARTED));
  EXPECT_EQ(h.state, BusState::ErrorActive);
  EXPECT_EQ(h.restarts, 1U);
  note_frame(h, error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_TX_PASSIVE));
  note_frame(h, error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_ACTIVE));
  EXPECT_EQ(h.state, BusState::ErrorActive) << "back to error-active";
  note_frame(h, error_frame(CAN_ERR_PROT | CAN_ERR_ACK));
  note_frame(h, error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_RX_OVERFLOW));
  EXPECT_EQ(h.error_frames, 9U);
  EXPECT_EQ(h.protocol_errors, 1U);
  EXPECT_EQ(h.no_ack, 1U);
  EXPECT_EQ(h.controller_overflows, 1U);
  EXPECT_EQ(h.state, BusState::ErrorActive) << "an overflow is not a state";
}

TEST(BusHealth, RemoteAndDataFrames) {
  BusHealth h;
  CanFrame rtr;
  rtr.rtr = true;
  rtr.id = 0x123;
  note_frame(h, rtr);
  CanFrame data;
  data.id = 0x123;
  data.len = 8;
  note_frame(h, data);
  EXPECT_EQ(h.remote_frames, 1U);
  EXPECT_EQ(h.error_frames, 0U);
  EXPECT_EQ(h.state, BusState::ErrorActive);
  CanFrame short_error;  // a truncated error frame reads missing bytes as 0, never past len
  short_error.error = true;
  short_error.id = CAN_ERR_CRTL | CAN_ERR_CNT;
  short_error.len = 1;
  short_error.data[1] = CAN_ERR_CRTL_RX_PASSIVE;
  short_error.data[6] = 200;
  note_frame(h, short_error);
  EXPECT_EQ(h.state, BusState::ErrorActive);
  EXPECT_EQ(h.tx_errors, 0);
  EXPECT_EQ(to_string(BusState::BusOff), "bus-off");
  EXPECT_NE(describe(h).find("error-active, 1 error frames"), std::string::npos) << describe(h);
}

TEST(BusHealth, SeveralBusesFoldIntoTheWorstStateAndSummedCounts) {
  BusHealth a, b, total;
  a.state = BusState::ErrorWarning;
  a.kernel_drops = 3;
  a.error_frames = 2;
  a.tx_errors = 90;
  b.state = BusState::BusOff;
  b.kernel_drops = 4;
  a.interface_drops = 5;
  b.interface_drops = 6;
  b.replay_slips = 1;
  b.tx_errors = 10;
  add_health(total, a);
  add_health(total, b);
  EXPECT_EQ(total.state, BusState::BusOff);
  EXPECT_EQ(total.kernel_drops, 7u);
  EXPECT_EQ(total.interface_drops, 11u);
  EXPECT_NE(describe(total).find(", 7 kernel drops, 11 interface drops, 1 replay slips"), std::string::npos)
      << describe(total);
  EXPECT_EQ(total.error_frames, 2u);
  EXPECT_EQ(total.replay_slips, 1u);
  EXPECT_EQ(total.tx_errors, 90);
}

}  // namespace
}  // namespace meter::controller
