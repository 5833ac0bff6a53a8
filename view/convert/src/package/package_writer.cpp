// The package writer: the Scene as the chunks of bridge/package_format.hpp, each section encoded by
// its records' field lists (record_encoder.hpp).
#include "meter/convert/package_writer.hpp"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>

#include "meter/bridge/package_format.hpp"
#include "meter/bridge/package_schema.hpp"
#include "record_encoder.hpp"

namespace meter::convert {

namespace {

template <class T>
void append(std::vector<std::uint8_t>& out, const T& v) {
  const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
  out.insert(out.end(), p, p + sizeof v);
}

}  // namespace

std::vector<std::uint8_t> serialize_scene(const Scene& s) {
  // The payload: one chunk per section of the scene, in its field list's order.
  std::vector<std::uint8_t> payload;
  bridge::fields(s, [&](const bridge::SceneSection& section, const auto& member) {
    RecordEncoder body;
    body.value(member);
    payload.insert(payload.end(), section.tag, section.tag + 4);
    append(payload, bridge::section_schema(member));
    append(payload, static_cast<std::uint64_t>(body.bytes.size()));
    payload.insert(payload.end(), body.bytes.begin(), body.bytes.end());
  });
  std::vector<std::uint8_t> out(std::begin(kPackageMagic), std::end(kPackageMagic));
  append(out, kPackageVersion);
  append(out, std::uint32_t{0});
  append(out, static_cast<std::uint64_t>(payload.size()));
  append(out, package_checksum(payload));
  out.insert(out.end(), payload.begin(), payload.end());
  return out;
}

void write_package(const Scene& scene, const std::string& path) {
  auto bytes = serialize_scene(scene);
  // A temporary name of this writer's own (process id and a per-process count), so two
  // conversions of the same package at once (two build jobs, two test processes) never write
  // into each other's file; the last rename wins and both leave a whole package.
  static std::atomic<unsigned> writes{0};
  const std::string tmp = path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(writes++);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw SceneError(path + ": cannot open " + tmp + " for writing: " + std::strerror(errno));
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
      std::remove(tmp.c_str());
      throw SceneError(path + ": write failed (" + tmp + ")");
    }
  }
  // Rename so a viewer never sees a half-written package.
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(tmp.c_str());
    throw SceneError(path + ": cannot rename " + tmp + " onto it: " + why);
  }
}

}  // namespace meter::convert
