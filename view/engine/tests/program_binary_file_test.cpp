// A kept program binary's file, pure: what is written reads back, and a file that is truncated,
// damaged, of another version or stored for another key is refused with what is wrong, before any
// byte reaches the driver.
#include <gtest/gtest.h>

#include "meter/engine/gl/program_binary_file.hpp"

using namespace meter::engine;

namespace {

const ProgramBinaryKey kKey = program_binary_key({"v", "r", "1"}, "vs", "fs");

ProgramBinary sample() { return ProgramBinary{0x8741, {1, 2, 3, 4, 5, 250, 251}}; }

std::string problem_of(const std::vector<std::uint8_t>& file, const ProgramBinaryKey& key = kKey) {
  const DecodedProgramBinary d = decode_program_binary(file, key);
  EXPECT_NE(d.binary.has_value(), !d.problem.empty());
  return d.problem;
}

}  // namespace

TEST(ProgramBinaryFile, WhatIsWrittenReadsBack) {
  const DecodedProgramBinary d = decode_program_binary(encode_program_binary(kKey, sample()), kKey);
  ASSERT_TRUE(d.binary) << d.problem;
  EXPECT_EQ(d.binary->format, 0x8741u);
  EXPECT_EQ(d.binary->bytes, sample().bytes);
}

TEST(ProgramBinaryFile, AnEmptyBinaryReadsBack) {
  EXPECT_EQ(problem_of(encode_program_binary(kKey, ProgramBinary{7, {}})), "");
}

TEST(ProgramBinaryFile, ATruncatedFileIsRefused) {
  auto file = encode_program_binary(kKey, sample());
  EXPECT_NE(problem_of({file.begin(), file.begin() + 40}).find("truncated: 40 bytes, the header needs 88"), std::string::npos);
  file.pop_back();
  EXPECT_NE(problem_of(file).find("says 7 bytes of binary, the file holds 6"), std::string::npos);
  EXPECT_NE(problem_of({}).find("truncated"), std::string::npos);
}

TEST(ProgramBinaryFile, ADamagedBinaryIsRefused) {
  auto file = encode_program_binary(kKey, sample());
  file.back() ^= 0x01;
  EXPECT_NE(problem_of(file).find("does not match its digest"), std::string::npos);
  file = encode_program_binary(kKey, sample());
  file[50] ^= 0x80;  // the stored digest itself
  EXPECT_NE(problem_of(file).find("does not match its digest"), std::string::npos);
}

TEST(ProgramBinaryFile, AFileStoredForAnotherKeyIsRefused) {
  const ProgramBinaryKey other = program_binary_key({"v", "r", "2"}, "vs", "fs");  // another driver version
  EXPECT_NE(problem_of(encode_program_binary(other, sample())).find("another driver or other sources"), std::string::npos);
}

TEST(ProgramBinaryFile, AnotherFormatOrVersionIsRefused) {
  auto file = encode_program_binary(kKey, sample());
  file[0] = 'X';
  EXPECT_NE(problem_of(file).find("not a meter program binary"), std::string::npos);
  file = encode_program_binary(kKey, sample());
  file[8] = 2;
  EXPECT_NE(problem_of(file).find("file version 2 at offset 8, expected 1"), std::string::npos);
}
