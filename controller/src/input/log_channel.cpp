// log:FILE#N: the channel suffix and the frames of that channel.
#include "meter/controller/input/log_channel.hpp"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "meter/controller/input/log_format.hpp"

namespace meter::controller {

LogAddress parse_log_address(const std::string& address) {
  const std::size_t hash = address.rfind('#');
  if (hash == std::string::npos || hash + 1 == address.size() || hash + 4 < address.size() ||
      !std::all_of(address.begin() + static_cast<std::ptrdiff_t>(hash) + 1, address.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return {address, 0};
  std::error_code ec;
  if (std::filesystem::exists(address, ec)) return {address, 0};  // a file whose name ends in #N
  const int channel = std::stoi(address.substr(hash + 1));
  if (channel < 1 || channel > 255)
    throw std::invalid_argument("log:" + address + ": channel " + std::to_string(channel) + ", expected #1..#255 after the file");
  return {address.substr(0, hash), channel};
}

std::unique_ptr<LogSource> open_log_input(const std::string& address) {
  const LogAddress a = parse_log_address(address);
  return open_log_source(a.path, a.channel);
}

}  // namespace meter::controller
