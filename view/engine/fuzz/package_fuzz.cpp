// Fuzzes the scene package (.msp) reader the way meter-view uses a package: deserialize the bytes
// (header, checksum, the chunks and every section in them, the embedded scene config,
// cross-references), then run the loaded scene through the bindings and scene evaluation for a few
// frames (exercise_scene). A
// rejected package must be a SceneError (from the reader, or from the bindings resolving the
// embedded config's names), and a package that loads must never index out of range.
//
// An input with the package magic gets its header's payload size and checksum rewritten to match
// its payload first, or nearly every mutation would stop at the checksum and the sections behind it
// would go unfuzzed (the checksum and size checks themselves are unit-tested). The seeds are written
// by the build from the current writer (view/convert/fuzz/CMakeLists.txt).
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "exercise_scene.hpp"
#include "meter/engine/package_reader.hpp"

using namespace meter::engine;
using meter::bridge::kPackageHeaderSize;
using meter::bridge::kPackageMagic;
using meter::bridge::package_checksum;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> input(data, data + size);
  if (size >= kPackageHeaderSize && std::memcmp(data, kPackageMagic, sizeof kPackageMagic) == 0) {
    const std::uint64_t payload_size = size - kPackageHeaderSize;
    const std::uint64_t checksum = package_checksum(std::span<const std::uint8_t>(input).subspan(kPackageHeaderSize));
    for (int i = 0; i < 8; ++i) {
      input[16 + i] = static_cast<std::uint8_t>(payload_size >> (8 * i));
      input[24 + i] = static_cast<std::uint8_t>(checksum >> (8 * i));
    }
  }
  const std::span<const std::uint8_t> bytes(input);
  Scene scene;
  PackageNotes notes;  // skipped chunks: what meter-view would log
  try {
    scene = deserialize_scene(bytes, "fuzz.msp", &notes);
  } catch (const SceneError&) {
    return 0;
  }
  try {
    fuzz::exercise_scene(scene, bytes.last(std::min<std::size_t>(size, 64)));
  } catch (const SceneError&) {
    // The bindings resolve the embedded config's names when the renderer starts (a package can
    // name a node it lacks); meter-view reports that SceneError and exits, as it does a bad read.
  }
  return 0;
}
