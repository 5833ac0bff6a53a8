// Linked programs kept across runs as the driver's own binaries (glGetProgramBinary /
// glProgramBinary), one file per driver and program in a cache directory, so a view started again
// hands the driver back what it linked last time instead of compiling and linking every program:
// production engines ship precompiled shaders the same way.
//
// A binary is used only when everything says it is this driver's program: the file's key (driver
// strings and both sources, program_binary_key.hpp) and digest (program_binary_file.hpp) match, the
// driver accepts it and the program links. A missing, stale (other sources, another driver),
// damaged or refused binary falls back to compiling the sources, so the image is the compiled
// program's either way; what was refused is logged and replaced. A file is written under a
// temporary name and renamed into place, so a reader never sees half a file, even with several
// views storing the same program at once. A directory that cannot be written costs the compile
// only (said once in the log).
//
// With Mesa (llvmpipe) the binary holds the linked program; llvmpipe's machine code for it is kept
// by Mesa's own shader cache (MESA_SHADER_CACHE_DIR, else $XDG_CACHE_HOME/mesa_shader_cache), and
// Mesa offers no binary format while that cache is switched off (MESA_SHADER_CACHE_DISABLE).
#pragma once

#include <cstddef>
#include <filesystem>
#include <ostream>
#include <string_view>

#include "meter/engine/gl/program_binary_key.hpp"
#include "meter/platform/gl_api.hpp"

namespace meter::engine {

class ProgramBinaryCache {
 public:
  // `directory` is created when the first binary is stored. Messages go to `log` (which must
  // outlive the cache).
  ProgramBinaryCache(std::filesystem::path directory, std::ostream& log);

  // The program linked from the two sources: the kept binary when it is valid for this driver,
  // else compiled (platform::compile_program, `label` in its errors) and its binary stored.
  GLuint link(const platform::Gl& gl, std::string_view vertex_source, std::string_view fragment_source,
              std::string_view label);

  struct Counts {
    std::size_t loaded = 0;    // programs made from a kept binary
    std::size_t compiled = 0;  // programs compiled from their sources
    std::size_t refused = 0;   // kept binaries found but not used (damaged, stale, refused by the driver)
    std::size_t stored = 0;    // binaries written
  };
  const Counts& counts() const { return counts_; }
  const std::filesystem::path& directory() const { return directory_; }

 private:
  GLuint load(const platform::Gl& gl, const std::filesystem::path& file, const ProgramBinaryKey& key);
  void store(const platform::Gl& gl, GLuint program, const std::filesystem::path& file, const ProgramBinaryKey& key);
  void refuse(const std::filesystem::path& file, std::string_view why);

  std::filesystem::path directory_;
  std::ostream& log_;
  Counts counts_;
  bool said_unsupported_ = false, said_unwritable_ = false;
};

// Where the view keeps program binaries by default: $XDG_CACHE_HOME/meter, else $HOME/.cache/meter
// (the XDG base-directory rule; an empty or relative $XDG_CACHE_HOME is ignored, as that rule
// says); empty when neither is set. The arguments are the two variables' values (null: unset).
std::filesystem::path default_program_cache_directory(const char* xdg_cache_home, const char* home);

}  // namespace meter::engine
