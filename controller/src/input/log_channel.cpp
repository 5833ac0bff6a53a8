// log:FILE#N: the channel suffix and the frames of that channel.
#include "meter/controller/input/log_channel.hpp"

#include <algorithm>
#include <bitset>
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

ParsedLog select_log_channel(ParsedLog log, int channel, const std::string& path) {
  if (channel == 0) return log;
  std::bitset<256> present;
  for (const CanFrame& f : log.frames) present.set(f.channel);
  std::erase_if(log.frames, [&](const CanFrame& f) { return f.channel != channel; });
  if (log.frames.empty()) {
    std::string channels;
    for (int c = 0; c < 256; ++c)
      if (present[static_cast<std::size_t>(c)]) channels += (channels.empty() ? "" : ", ") + (c == 0 ? std::string("none") : std::to_string(c));
    throw std::runtime_error(path + "#" + std::to_string(channel) + ": no frame on channel " + std::to_string(channel) +
                             " (the log's channels: " + channels + ")");
  }
  return log;
}

ParsedLog load_log_input(const std::string& address) {
  const LogAddress a = parse_log_address(address);
  return select_log_channel(load_log_file(a.path), a.channel, a.path);
}

}  // namespace meter::controller
