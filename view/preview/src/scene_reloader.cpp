#include "meter/preview/scene_reloader.hpp"

#include <exception>

#include "meter/config/scene_config_parser.hpp"
#include "meter/convert/converter.hpp"
#include "meter/convert/package_writer.hpp"
#include "meter/engine/package_reader.hpp"
#include "meter/protocol/catalog.hpp"

namespace meter::preview {

std::unique_ptr<engine::Scene> convert_scene(const SceneFiles& files, const protocol::Catalog& catalog,
                                             shadergen::ProgramCache* programs) {
  const auto config = meter::config::load_scene_config(files.config, catalog);
  convert::ConvertOptions options;
  options.program_cache = programs;
  const auto result = convert::convert_gltf(files.gltf, config, options);
  const auto bytes = convert::serialize_scene(result.scene);
  return std::make_unique<engine::Scene>(engine::deserialize_scene(bytes, files.gltf));
}

SceneReloader::SceneReloader(SceneFiles files, std::chrono::milliseconds settle)
    : files_(std::move(files)), settle_(settle) {}

void SceneReloader::changed(Clock::time_point now) {
  if (!pending_) first_change_ = now;
  pending_ = true;
  last_change_ = now;
}

bool SceneReloader::due(Clock::time_point now) const { return pending_ && now - last_change_ >= settle_; }

bool SceneReloader::reload() {
  begin();
  job_.wait();
  return *finish();
}

void SceneReloader::begin() {
  if (job_.valid()) job_.wait();  // one conversion at a time; its result is replaced by this one's
  pending_ = false;
  job_change_ = first_change_;
  job_began_ = Clock::now();
  // The catalog is taken here, on the caller's thread: the worker sees the one active at the save.
  job_ = std::async(std::launch::async, [files = files_, catalog = protocol::active_catalog(), programs = programs_] {
    return convert_scene(files, *catalog, programs.get());
  });
}

std::optional<bool> SceneReloader::finish() {
  if (!job_.valid() || job_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return std::nullopt;
  try {
    std::shared_ptr<const engine::Scene> next = job_.get();
    convert_ms_ = std::chrono::duration<double, std::milli>(Clock::now() - job_began_).count();
    scene_ = std::move(next);
    ++generation_;
    error_.clear();
    return true;
  } catch (const std::exception& e) {
    convert_ms_ = std::chrono::duration<double, std::milli>(Clock::now() - job_began_).count();
    error_ = e.what();
    return false;
  }
}

}  // namespace meter::preview
