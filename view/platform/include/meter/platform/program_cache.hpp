// Linked GL programs kept by their sources, shared by everything drawn in one context: a renderer
// made again for an edited scene (the preview's reload) gets the programs an earlier renderer
// linked for the same sources instead of compiling them anew. On a software rasteriser that is most
// of a reload: llvmpipe compiles each program's machine code at its first draw (about 1.3 s for the
// cluster's programs with Mesa's disk cache off, still 70-130 ms with it on), and a kept program
// keeps that code.
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

}  // namespace meter::platform
