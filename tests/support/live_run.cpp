#include "live_run.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace fs = std::filesystem;

namespace meter::testing {

std::vector<std::map<std::string, std::string>> read_csv(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream s(line);
    std::string cell;
    while (std::getline(s, cell, ',')) cells.push_back(cell);
    if (header.empty()) {
      header = cells;
      continue;
    }
    if (cells.size() < header.size()) continue;
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < header.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

void convert_minimal_gauge(const fs::path& msp) {
  const std::string source = METER_SOURCE_DIR;
  ChildProcess convert({built_executable("meter-convert"), source + "/scenes/minimal-gauge/minimal-gauge.glb",
                        "--config", source + "/scenes/minimal-gauge/minimal-gauge.scene.json", "-o", msp.string()},
                       msp.string() + ".convert.log");
  const auto rc = convert.wait_for(std::chrono::seconds(60));
  if (!rc) throw std::runtime_error("meter-convert hung");
  if (*rc != 0) throw std::runtime_error("meter-convert failed:\n" + convert.log());
}

void wait_for_first_dump(const fs::path& frames_csv, ChildProcess& view, std::chrono::seconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!fs::exists(frames_csv) || read_csv(frames_csv).empty()) {
    if (!view.running()) throw std::runtime_error("meter-view ended before its first frame:\n" + view.log());
    if (std::chrono::steady_clock::now() > deadline) {
      throw std::runtime_error("meter-view dumped no frame in " + std::to_string(timeout.count()) + " s:\n" + view.log());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

}  // namespace meter::testing
