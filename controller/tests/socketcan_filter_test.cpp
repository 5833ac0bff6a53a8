// The SocketCAN kernel id filter built from what the mapping reads: exact ids for ordinary
// messages, a PGN mask for J1939 parameter groups (any priority, any source address and, for
// PDU1 groups, any destination), and never "receive everything" because of J1939.
#include <gtest/gtest.h>

#include <string>

#include "../src/run/open_input.hpp"
#include "meter/controller/dbc/database.hpp"
#include "meter/controller/input/can_id_filter.hpp"
#include "meter/controller/mapping/mapping.hpp"
#include "meter/controller/model/model.hpp"

namespace meter::controller {
namespace {

const std::string kDir = std::string(METER_SOURCE_DIR) + "/controller/tests/data/";

TEST(SocketCanFilter, J1939MessagesKeepKernelFilteringOn) {
  Database db = load_dbc(kDir + "socketcan_buses.dbc");
  Model model(&db, load_mapping(kDir + "socketcan_buses.map"));
  const auto used = model.used_ids();
  ASSERT_EQ(used.size(), 3u) << "EEC1, ABS_FD and Body";
  const auto filters = can_filters(used, &db);
  EXPECT_EQ(filters.size(), used.size()) << "one kernel filter per used message, J1939 ones included";
  // EEC1 (PGN 0xF004, a PDU2 group): any priority, any source address.
  for (std::uint32_t id : {0x0CF004FEu, 0x0CF00400u, 0x18F00417u, 0x1CF004A5u})
    EXPECT_TRUE(filters_accept(filters, id, true)) << std::hex << id;
  EXPECT_FALSE(filters_accept(filters, 0x0CF005FEu, true)) << "another parameter group";
  EXPECT_FALSE(filters_accept(filters, 0x18FEF1FEu, true)) << "CCVS1: in the DBC, not in the mapping";
  EXPECT_FALSE(filters_accept(filters, 0x0CF004FEu, false)) << "11-bit frames never match a 29-bit filter";
  // ABS_FD (extended, not J1939) and Body (11 bit): exact ids only.
  EXPECT_TRUE(filters_accept(filters, 0x1D00F001u, true));
  EXPECT_FALSE(filters_accept(filters, 0x1D00F002u, true));
  EXPECT_TRUE(filters_accept(filters, 0x123u, false));
  EXPECT_FALSE(filters_accept(filters, 0x124u, false));
  EXPECT_FALSE(filters_accept(filters, 0x123u, true));
}

TEST(SocketCanFilter, Pdu1GroupsIgnoreTheDestinationAddress) {
  // PGN 0xEF00 (PF 0xEF < 240): byte PS is a destination, so every destination and source passes.
  const std::vector<CanIdFilter> f = {j1939_group_filter(0x18EF2100u)};
  EXPECT_EQ(f[0].mask, 0x03FF0000u);
  EXPECT_TRUE(filters_accept(f, 0x18EF0017u, true));
  EXPECT_TRUE(filters_accept(f, 0x0CEFFFFEu, true));
  EXPECT_FALSE(filters_accept(f, 0x18EE2100u, true));
  // The decoder's own PGN rule agrees with the filter on every accepted id.
  EXPECT_EQ(j1939_pgn(0x18EF0017u), j1939_pgn(0x18EF2100u));
  EXPECT_EQ(j1939_group_filter(0x0CF004FEu).mask, 0x03FFFF00u);
}

TEST(SocketCanFilter, NoFilterAcceptsEverything) {
  EXPECT_TRUE(filters_accept({}, 0x7FFu, false));
  EXPECT_TRUE(filters_accept({}, 0x1FFFFFFFu, true));
  EXPECT_EQ(effective_mask(CanIdFilter{0x123, false, 0}), 0x7FFu);
  EXPECT_EQ(effective_mask(CanIdFilter{0x123, true, 0}), 0x1FFFFFFFu);
}

}  // namespace
}  // namespace meter::controller
