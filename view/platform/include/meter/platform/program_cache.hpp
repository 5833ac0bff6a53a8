// Linked GL programs kept by their sources, shared by everything drawn in one context: a renderer
// made again for an edited scene (the preview's reload) gets the programs an earlier renderer
// linked for the same sources instead of compiling them anew. On a software rasteriser that is most
// of a reload: llvmpipe compiles each program's machine code at its first draw (the cluster's first
// frame took 1.25-1.65 s with Mesa's disk shader cache off; with it on, looking the programs up and
// linking them still cost 20-90 ms a reload), and a kept program keeps that code.
//
// Every program handed out is counted until released; trim() deletes the ones no one holds. The
// cache must outlive every holder and be used with its context current.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <unordered_map>

#include "meter/platform/gl_api.hpp"

namespace meter::platform {

class ProgramCache {
 public:
  explicit ProgramCache(const Gl& gl) : gl_(gl) {}
  ~ProgramCache();
  ProgramCache(const ProgramCache&) = delete;
  ProgramCache& operator=(const ProgramCache&) = delete;

  // The program linked from these two sources, compiled (compile_program, with `label` in its
  // errors) at the first request, the same name at every later one while it is held or not yet
  // trimmed. Each call holds the program once more.
  GLuint acquire(std::string_view vertex_source, std::string_view fragment_source, std::string_view label);
  // Gives back one hold of a program acquire() returned (anything else is ignored). A program
  // nobody holds stays linked until trim().
  void release(GLuint program);
  // Deletes the programs nobody holds (an old scene's, after the new one took its programs);
  // returns how many.
  std::size_t trim();

  std::size_t size() const { return programs_.size(); }  // linked programs, held or not
  std::size_t compiles() const { return compiles_; }      // acquire() calls that had to link

 private:
  struct Entry {
    std::string key;  // the two sources
    int holds = 0;
  };
  const Gl& gl_;
  std::unordered_map<std::string, GLuint> by_source_;
  std::unordered_map<GLuint, Entry> programs_;
  std::size_t compiles_ = 0;
};

// For the owners of a program that may or may not share a cache (`cache` null: the program is the
// owner's alone): the program linked from the two sources, acquired from the cache or compiled...
GLuint acquire_program(ProgramCache* cache, const Gl& gl, std::string_view vertex_source,
                       std::string_view fragment_source, std::string_view label);
// ...and given back to the cache or deleted (0: nothing).
void release_program(ProgramCache* cache, const Gl& gl, GLuint program);

}  // namespace meter::platform
