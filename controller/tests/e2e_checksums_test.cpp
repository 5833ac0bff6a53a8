// The checksum algorithms of the E2E stage against published values: the AUTOSAR CRC library's
// check values and example table, the E2E protocol specification's profile examples, and frames
// recorded on the cars (or worked examples) the makes' public descriptions give.
#include <gtest/gtest.h>

#include <string_view>
#include <utility>
#include <vector>

#include "meter/controller/dbc/codec.hpp"
#include "meter/controller/dbc/database.hpp"
#include "meter/controller/e2e/autosar_profile01.hpp"
#include "meter/controller/e2e/autosar_profile02.hpp"
#include "meter/controller/e2e/autosar_profile05.hpp"
#include "meter/controller/e2e/autosar_profile11.hpp"
#include "meter/controller/e2e/chrysler_checksum.hpp"
#include "meter/controller/e2e/crc16_ccitt.hpp"
#include "meter/controller/e2e/crc8_sae_j1850.hpp"
#include "meter/controller/e2e/crc8h2f.hpp"
#include "meter/controller/e2e/honda_checksum.hpp"
#include "meter/controller/e2e/hyundai_canfd_checksum.hpp"
#include "meter/controller/e2e/hyundai_checksum.hpp"
#include "meter/controller/e2e/mazda_checksum.hpp"
#include "meter/controller/e2e/nissan_checksum.hpp"
#include "meter/controller/e2e/subaru_checksum.hpp"
#include "meter/controller/e2e/subaru_preglobal_checksum.hpp"
#include "meter/controller/e2e/tesla_checksum.hpp"
#include "meter/controller/e2e/toyota_checksum.hpp"
#include "meter/controller/e2e/vw_mqb_checksum.hpp"

namespace meter::controller {
namespace {

using Bytes = std::vector<std::uint8_t>;
const Bytes kCheck = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};

// The AUTOSAR CRC library specification's example data (SWS_Crc, "Check values" tables).
const std::vector<Bytes> kExamples = {
    {0x00, 0x00, 0x00, 0x00}, {0xF2, 0x01, 0x83}, {0x0F, 0xAA, 0x00, 0x55}, {0x00, 0xFF, 0x55, 0x11},
    {0x33, 0x22, 0x55, 0xAA, 0xBB, 0xCC, 0xDD, 0xEE, 0xFF}, {0x92, 0x6B, 0x55}, {0xFF, 0xFF, 0xFF, 0xFF}};

TEST(E2eCrc, Crc8SaeJ1850MatchesTheLibrarySpecification) {
  EXPECT_EQ(crc8_sae_j1850(kCheck), 0x4B);
  const std::uint8_t want[] = {0x59, 0x37, 0x79, 0xB8, 0xCB, 0x8C, 0x74};
  for (std::size_t i = 0; i < kExamples.size(); ++i) EXPECT_EQ(crc8_sae_j1850(kExamples[i]), want[i]) << "example " << i;
}

TEST(E2eCrc, Crc8H2FMatchesTheLibrarySpecification) {
  EXPECT_EQ(crc8h2f(kCheck), 0xDF);
  const std::uint8_t want[] = {0x12, 0xC2, 0xC6, 0x77, 0x11, 0x33, 0x6C};
  for (std::size_t i = 0; i < kExamples.size(); ++i) EXPECT_EQ(crc8h2f(kExamples[i]), want[i]) << "example " << i;
}

TEST(E2eCrc, Crc16CcittFalseMatchesTheLibrarySpecification) {
  EXPECT_EQ(crc16_ccitt_false(kCheck), 0x29B1);
  const std::uint16_t want[] = {0x84C0, 0xD374, 0x2023, 0xB8F9, 0xF53F, 0x0745, 0x1D0F};
  for (std::size_t i = 0; i < kExamples.size(); ++i) EXPECT_EQ(crc16_ccitt_false(kExamples[i]), want[i]) << "example " << i;
}

// The E2E protocol specification's examples: data id 0x123, eight bytes, counter 0, data zero.
TEST(E2eProfiles, Profile11AndProfile1MatchTheSpecificationExamples) {
  Bytes both(8, 0);
  EXPECT_EQ(autosar_profile11_crc(both, 0, 0x123, DataIdMode::Both), 0xCC);
  EXPECT_EQ(autosar_profile01_crc(both, 0, 0x123, DataIdMode::Both, 0), 0xCC);
  Bytes nibble(8, 0);
  nibble[1] = 0x10;  // the data id's high nibble (1) in bits 12..15, counter 0 in bits 8..11
  EXPECT_EQ(autosar_profile11_crc(nibble, 0, 0x123, DataIdMode::Nibble), 0x2A);
  EXPECT_TRUE(autosar_profile11_nibble_ok(nibble, 0x123, DataIdMode::Nibble));
  EXPECT_FALSE(autosar_profile11_nibble_ok(both, 0x123, DataIdMode::Nibble));
  // Alternating mode covers the low byte on even counters, the high byte on odd ones; Low mode
  // is the even case of Alternating.
  Bytes odd(8, 0);
  odd[1] = 0x01;
  EXPECT_EQ(autosar_profile01_crc(both, 0, 0x123, DataIdMode::Alternating, 0), autosar_profile01_crc(both, 0, 0x123, DataIdMode::Low, 0));
  EXPECT_EQ(autosar_profile01_crc(odd, 0, 0x123, DataIdMode::Alternating, 1), autosar_profile01_crc(odd, 0, 0x101, DataIdMode::Low, 1));
}

// The E2E protocol specification's Profile 1 example table (its chapter on Profile 1's examples):
// data id 0x123, CRC in byte 0, the counter in byte 1's low nibble (and in Nibble mode the data id's
// high nibble in its high nibble), data zero, counters 0 and 1 in each data id mode. An independent
// open implementation's tests of that chapter carry the same eight values.
TEST(E2eProfiles, Profile1MatchesTheSpecificationsExampleTable) {
  struct Row {
    DataIdMode mode;
    std::uint8_t byte1;
    unsigned counter;
    std::uint8_t crc;
  };
  const Row rows[] = {{DataIdMode::Both, 0x00, 0, 0xCC},        {DataIdMode::Both, 0x01, 1, 0x91},
                      {DataIdMode::Alternating, 0x00, 0, 0xCE}, {DataIdMode::Alternating, 0x01, 1, 0x02},
                      {DataIdMode::Low, 0x00, 0, 0xCE},         {DataIdMode::Low, 0x01, 1, 0x93},
                      {DataIdMode::Nibble, 0x10, 0, 0x2A},      {DataIdMode::Nibble, 0x11, 1, 0x77}};
  for (const Row& r : rows) {
    Bytes frame(8, 0);
    frame[1] = r.byte1;
    EXPECT_EQ(autosar_profile01_crc(frame, 0, 0x123, r.mode, r.counter), r.crc)
        << "mode " << static_cast<int>(r.mode) << ", counter " << r.counter;
  }
}

TEST(E2eProfiles, Profile5MatchesTheSpecificationExamples) {
  // Data id 0x1234, eight bytes, counter 0, data zero: CRC bytes 0x1C 0xCA (little-endian 0xCA1C).
  EXPECT_EQ(autosar_profile05_crc(Bytes(8, 0), 0, 0x1234), 0xCA1C);
  // The same with the header at byte 8 of sixteen: CRC bytes 0x28 0x91.
  EXPECT_EQ(autosar_profile05_crc(Bytes(16, 0), 8, 0x1234), 0x9128);
}

// Frames recorded on MQB cars (opendbc's checksum tests): byte 0 is profile 2's CRC over the
// rest and the message's data id for the counter in byte 1's low nibble.
TEST(E2eMakes, VwMqbMatchesRecordedFrames) {
  const std::pair<std::uint32_t, Bytes> frames[] = {
      {0x086, {0x6B, 0x00, 0xBD, 0x00, 0x00, 0x00, 0x00, 0x00}},  // LWI_01, counter 0
      {0x086, {0x60, 0x0F, 0x62, 0xC0, 0x00, 0x00, 0x00, 0x00}},  // LWI_01, counter 15
      {0x0FD, {0x66, 0xD0, 0x1F, 0x80, 0x45, 0x05, 0x00, 0x00}},  // ESP_21, counter 0
      {0x0FD, {0xFB, 0xDF, 0x1F, 0x80, 0x46, 0x00, 0x00, 0x00}},  // ESP_21, counter 15
      {0x0AD, {0xF8, 0xE0, 0xBF, 0xFF, 0x5F, 0x20, 0x20, 0x20}},  // Getriebe_11
      {0x121, {0x0E, 0x55, 0x20, 0x60, 0x18, 0x46, 0x7E, 0xFE}},  // Motor_20, counter 5
      {0x12B, {0x0D, 0x4F, 0x80, 0x2A, 0x00, 0x00, 0x00, 0x00}},  // GRA_ACC_01, counter 15
      {0x3C0, {0x74, 0x00, 0x03, 0x00}},                          // Klemmen_Status_01, four bytes
      {0x65D, {0x72, 0x3F, 0x2B, 0x10, 0x00, 0x00, 0x22, 0x81}},  // ESP_20, counter 15
  };
  for (const auto& [id, f] : frames) {
    const auto crc = vw_mqb_checksum(id, f);
    ASSERT_TRUE(crc) << std::hex << id;
    EXPECT_EQ(*crc, f[0]) << std::hex << id;
  }
  EXPECT_FALSE(vw_mqb_checksum(0x7FF, frames[0].second));  // no data id list known: not guessed
}

// opendbc's Honda test: LKAS_HUD (11-bit id) and LKAS_HUD_A (29-bit id) with the same signal values
// carry checksums 11, 10, 9, 8 and 4, 3, 2, 1 for counters 0..3.
TEST(E2eMakes, HondaMatchesOpendbcsKnownChecksums) {
  const Database db = load_dbc(std::string(METER_SHARED_DIR) + "/data/can/opendbc/honda_accord_2018_can_generated.dbc");
  const int want_std[] = {11, 10, 9, 8}, want_ext[] = {4, 3, 2, 1};
  for (int counter = 0; counter < 4; ++counter) {
    const std::pair<std::string_view, double> values[] = {
        {"SET_ME_X41", 0x41}, {"STEERING_REQUIRED", 1}, {"SOLID_LANES", 1}, {"BEEP", 0}, {"COUNTER", counter}};
    const DbcMessage* hud = db.find("LKAS_HUD");
    const DbcMessage* hud_a = db.find("LKAS_HUD_A");
    ASSERT_TRUE(hud && hud_a);
    EXPECT_EQ(honda_checksum(hud->id, hud->extended, encode(*hud, values)), want_std[counter]);
    EXPECT_EQ(honda_checksum(hud_a->id, true, encode(*hud_a, values)), want_ext[counter]);
  }
}

TEST(E2eMakes, ChryslerAndNissanAreJ1850OverAllButTheLastByte) {
  const Bytes frame = {0x14, 0x00, 0x00, 0x00, 0x20, 0xCC};  // chryslercan's worked example: good checksum 0xCC
  EXPECT_EQ(chrysler_checksum(frame), 0xCC);
  EXPECT_EQ(nissan_checksum(frame), 0xCC);
}

TEST(E2eMakes, MazdaMatchesItsWorkedExample) {
  EXPECT_EQ(mazda_checksum(Bytes{0xB8, 0x00, 0x00, 0x20, 0x02, 0x00, 0x00, 0xC4}), 0xC4);  // 249 - 0xB - 0x8 - 0x20 - 0x02
}

// Rules with no published frame: each is checked on a frame worked by hand from its description,
// so a change of the arithmetic (a byte left in or out) fails.
TEST(E2eMakes, SumChecksumsFollowTheirDescriptions) {
  // Toyota: length 5 + id bytes 0x02 + 0xE4 + payload 0x80 -> 0x16B -> 0x6B.
  EXPECT_EQ(toyota_checksum(0x2E4, Bytes{0x80, 0x00, 0x00, 0x00, 0x00}), 0x6B);
  // Subaru global: id 0x119 (0x01 + 0x19) + bytes 1.. (0x10 + 0x20) -> 0x4A; byte 0 left out.
  EXPECT_EQ(subaru_checksum(0x119, Bytes{0xFF, 0x10, 0x20}), 0x4A);
  // Subaru pre-global: every byte but the checksum's (byte 4), no id: 0x5A + 0x70 + 0x0D -> 0xD7.
  EXPECT_EQ(subaru_preglobal_checksum(Bytes{0x00, 0x5A, 0x70, 0x0D, 0x99, 0x00, 0x00, 0x00}, 4), 0xD7);
  // Tesla: id 0x370 (0x70 + 0x03) + every byte but the checksum's (byte 7): 0x73 + 0x10 -> 0x83.
  EXPECT_EQ(tesla_checksum(0x370, Bytes{0x10, 0, 0, 0, 0, 0, 0, 0x55}, 7), 0x83);
  // Hyundai nibble sum: nibbles 1 + 2 + 3 (the checksum nibble, bits 60..63, counted as 0) = 6 -> 10.
  EXPECT_EQ(hyundai_checksum(Bytes{0x21, 0x03, 0, 0, 0, 0, 0, 0xF0}, 60), 10);
  // Honda, extended id: 3 more than the standard id's checksum over the same nibbles.
  EXPECT_EQ(honda_checksum(0x33DA, true, Bytes{0x41, 0x05, 0x00, 0x00, 0x00}),
            (honda_checksum(0x33DA, false, Bytes{0x41, 0x05, 0x00, 0x00, 0x00}) + 3) & 0x0F);
}

TEST(E2eMakes, HyundaiCanFdDefinesFourLengths) {
  EXPECT_TRUE(hyundai_canfd_checksum(0x12A, Bytes(8, 0)));
  EXPECT_TRUE(hyundai_canfd_checksum(0x12A, Bytes(32, 0)));
  EXPECT_FALSE(hyundai_canfd_checksum(0x12A, Bytes(12, 0)));
  // Lengths differ only in the final constant: 8 vs 16 bytes of zeros share the register up to it.
  const Bytes z8(8, 0);
  EXPECT_EQ(*hyundai_canfd_checksum(0x100, z8) ^ 0x5F29, crc16_ccitt_update(crc16_ccitt_update(0, Bytes(6, 0)), Bytes{0x00, 0x01}));
}

}  // namespace
}  // namespace meter::controller
