// The reload logic: the artist's glTF + scene config converted in-process into the scene the
// runtime draws, again after every save, keeping the last good scene when a save does not convert.
// No window and no GL: the preview loop builds the renderer for each new scene.
#pragma once

#include <chrono>
#include <cstdint>
#include <future>
#include <memory>
#include <optional>
#include <string>

#include "meter/engine/vocabulary.hpp"
#include "meter/protocol/catalog.hpp"
#include "meter/shadergen/program_cache.hpp"

namespace meter::preview {

struct SceneFiles {
  std::string gltf;    // .glb / .gltf the artist exports
  std::string config;  // the scene config (meter-scene-config/1)
};

// Converts the files as meter-convert does and reads the result back through the package format,
// so the scene is exactly the one meter-view loads from the .msp. Bindings are checked against
// `catalog`. Programs optimized before come from `programs` (null: none kept), byte-identical to
// fresh ones. Throws (SceneError and its kinds) with the converter's text.
std::unique_ptr<engine::Scene> convert_scene(const SceneFiles& files, const protocol::Catalog& catalog,
                                             shadergen::ProgramCache* programs = nullptr);

class SceneReloader {
 public:
  using Clock = std::chrono::steady_clock;
  // A save is often several events (write, close, rename; both files exported together): a reload
  // starts once `settle` passed without another change. 40 ms covers an exporter writing the .glb
  // and the config one after the other and leaves most of the one-second budget to the conversion.
  static constexpr std::chrono::milliseconds kSettle{40};

  explicit SceneReloader(SceneFiles files, std::chrono::milliseconds settle = kSettle);

  // A watched file changed at `now`.
  void changed(Clock::time_point now);
  // True once a change is pending and `settle` has passed since the last one.
  bool due(Clock::time_point now) const;
  // A change is waiting for its reload.
  bool pending() const { return pending_; }
  // When the first change of the pending reload arrived (for the reload latency).
  Clock::time_point first_change() const { return first_change_; }

  // Converts now (clears the pending change). true: scene() is the new scene and generation()
  // went up by one; false: error() holds the converter's message and scene() is still the last
  // good scene (null when there never was one).
  bool reload();
  // The same on a worker thread, so the window keeps drawing while a large scene converts:
  // begin() starts it (clears the pending change; a save during the conversion makes a new one
  // pending), finish() returns nullopt while it runs, then once what reload() would have returned.
  // converting() is true in between; scene(), generation() and error() change only in finish().
  void begin();
  std::optional<bool> finish();
  bool converting() const { return job_.valid(); }
  // The first change of the save the running (or last finished) conversion is for.
  Clock::time_point converting_change() const { return job_change_; }

  std::shared_ptr<const engine::Scene> scene() const { return scene_; }
  std::uint64_t generation() const { return generation_; }
  const std::string& error() const { return error_; }
  double last_convert_ms() const { return convert_ms_; }
  // The optimized programs kept across reloads: a save that leaves a material's features and
  // constants alone reuses its program instead of optimizing it again.
  const shadergen::ProgramCache& programs() const { return *programs_; }
  const SceneFiles& files() const { return files_; }

 private:
  SceneFiles files_;
  std::chrono::milliseconds settle_;
  bool pending_ = false;
  Clock::time_point first_change_{}, last_change_{};
  std::shared_ptr<const engine::Scene> scene_;
  std::uint64_t generation_ = 0;
  std::string error_;
  double convert_ms_ = 0.0;
  std::shared_ptr<shadergen::ProgramCache> programs_ = std::make_shared<shadergen::ProgramCache>();
  std::future<std::unique_ptr<engine::Scene>> job_;
  Clock::time_point job_began_{}, job_change_{};
};

}  // namespace meter::preview
