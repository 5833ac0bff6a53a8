#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "meter/controller/input/log_format.hpp"
#include "meter/controller/run/convert_log_command.hpp"

using namespace meter::controller;

TEST(ConvertLog, EveryWriterRoundTripsAndBadRequestsSayWhy) {
  const auto dir = std::filesystem::temp_directory_path() / ("meter-convert-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string in = (dir / "in.log").string();
  std::ofstream(in) << "(1631416514.717133) can0 0D2#0000FFFF10000000\n(1631416514.717200) can1 18FEF100##3"
                    << std::string(24, 'A') << "\n(1631416514.718000) can0 7DF#R\n(1631416514.719000) can1 20000000#\n";  // ASC and BLF record no SocketCAN error class
  std::string chain = in;
  for (const char* ext : {".asc", ".blf", ".log"}) {
    const std::string next = (dir / (std::string("out") + ext)).string();
    std::ostringstream out, err;
    ASSERT_EQ(convert_log_command({chain, next, "", false}, out, err), 0) << err.str();
    EXPECT_NE(out.str().find(": 4 frames"), std::string::npos) << out.str();
    chain = next;
  }
  std::ifstream a(in), b(chain);
  std::stringstream sa, sb;
  sa << a.rdbuf();
  sb << b.rdbuf();
  EXPECT_EQ(sa.str(), sb.str());  // candump -> ASC -> BLF -> candump, byte for byte

  std::ostringstream out, err;
  EXPECT_EQ(convert_log_command({in, (dir / "x.trc").string(), "", false}, out, err), 1);
  EXPECT_NE(err.str().find("x.trc: the output format is not told by its extension; name one with --format: candump (.log), asc (.asc), blf (.blf)"),
            std::string::npos) << err.str();
  EXPECT_EQ(convert_log_command({in, in, "asc", false}, out, err), 1);
  EXPECT_NE(err.str().find("is the input itself"), std::string::npos) << err.str();
  EXPECT_EQ(convert_log_command({in + "#2", (dir / "two.log").string(), "", false}, out, err), 0) << err.str();
  EXPECT_EQ(read_whole_log(*open_log_source((dir / "two.log").string())).frames.size(), 2u);
  std::filesystem::remove_all(dir);
}
