// Programs shared by their sources: one link per distinct pair of sources while anyone holds it.
#include "meter/platform/program_cache.hpp"

namespace meter::platform {

namespace {

// Vertex and fragment source in one key; the length prefix keeps ("ab", "c") apart from ("a", "bc").
std::string key_of(std::string_view vertex_source, std::string_view fragment_source) {
  std::string key = std::to_string(vertex_source.size());
  key += ':';
  key += vertex_source;
  key += fragment_source;
  return key;
}

}  // namespace

ProgramCache::~ProgramCache() {
  for (const auto& [program, entry] : programs_) gl_.DeleteProgram(program);
}

GLuint ProgramCache::acquire(std::string_view vertex_source, std::string_view fragment_source, std::string_view label) {
  std::string key = key_of(vertex_source, fragment_source);
  if (const auto it = by_source_.find(key); it != by_source_.end()) {
    ++programs_.at(it->second).holds;
    return it->second;
  }
  const GLuint program = compile_program(gl_, vertex_source, fragment_source, label);  // throws: nothing stored
  ++compiles_;
  by_source_.emplace(key, program);
  programs_.emplace(program, Entry{std::move(key), 1});
  return program;
}

void ProgramCache::release(GLuint program) {
  const auto it = programs_.find(program);
  if (it != programs_.end() && it->second.holds > 0) --it->second.holds;
}

std::size_t ProgramCache::trim() {
  std::size_t deleted = 0;
  for (auto it = programs_.begin(); it != programs_.end();) {
    if (it->second.holds > 0) {
      ++it;
      continue;
    }
    gl_.DeleteProgram(it->first);
    by_source_.erase(it->second.key);
    it = programs_.erase(it);
    ++deleted;
  }
  return deleted;
}

GLuint acquire_program(ProgramCache* cache, const Gl& gl, std::string_view vertex_source,
                       std::string_view fragment_source, std::string_view label) {
  return cache ? cache->acquire(vertex_source, fragment_source, label)
               : compile_program(gl, vertex_source, fragment_source, label);
}

void release_program(ProgramCache* cache, const Gl& gl, GLuint program) {
  if (program == 0) return;
  if (cache)
    cache->release(program);
  else
    gl.DeleteProgram(program);
}

}  // namespace meter::platform
