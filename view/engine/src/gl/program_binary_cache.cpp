#include "meter/engine/gl/program_binary_cache.hpp"

#include <unistd.h>

#include <atomic>
#include <fstream>
#include <iterator>
#include <system_error>
#include <vector>

#include "meter/engine/gl/program_binary_file.hpp"

namespace meter::engine {

namespace fs = std::filesystem;

namespace {

std::vector<std::uint8_t> read_file(const fs::path& file, bool& found) {
  std::ifstream in(file, std::ios::binary);
  found = static_cast<bool>(in);
  if (!found) return {};
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void drain_gl_errors(const platform::Gl& gl) {
  for (int i = 0; i < 16 && gl.GetError() != GL_NO_ERROR; ++i) {
  }
}

// A name no other writer uses: this process, and a count within it.
fs::path temporary_name(const fs::path& file) {
  static std::atomic<unsigned> count{0};
  return fs::path(file.string() + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(count++));
}

}  // namespace

ProgramBinaryCache::ProgramBinaryCache(fs::path directory, std::ostream& log)
    : directory_(std::move(directory)), log_(log) {}

GLuint ProgramBinaryCache::link(const platform::Gl& gl, std::string_view vertex_source,
                                std::string_view fragment_source, std::string_view label) {
  if (!gl.info.has_program_binary) {
    if (!std::exchange(said_unsupported_, true))
      log_ << "program cache: the driver offers no program binary format (" << gl.info.renderer
           << "); programs are compiled at every start\n";
    ++counts_.compiled;
    return platform::compile_program(gl, vertex_source, fragment_source, label);
  }
  const DriverIdentity driver{gl.info.vendor, gl.info.renderer, gl.info.version};
  const ProgramBinaryKey key = program_binary_key(driver, vertex_source, fragment_source);
  const fs::path file = directory_ / program_binary_file_name(key);
  if (const GLuint program = load(gl, file, key)) {
    ++counts_.loaded;
    return program;
  }
  const GLuint program = platform::compile_program(gl, vertex_source, fragment_source, label);
  ++counts_.compiled;
  store(gl, program, file, key);
  return program;
}

GLuint ProgramBinaryCache::load(const platform::Gl& gl, const fs::path& file, const ProgramBinaryKey& key) {
  bool found = false;
  const std::vector<std::uint8_t> bytes = read_file(file, found);
  if (!found) return 0;
  DecodedProgramBinary decoded = decode_program_binary(bytes, key);
  if (!decoded.binary) {
    refuse(file, decoded.problem);
    return 0;
  }
  drain_gl_errors(gl);
  const GLuint program = gl.CreateProgram();
  gl.ProgramBinary(program, decoded.binary->format, decoded.binary->bytes.data(),
                   static_cast<GLsizei>(decoded.binary->bytes.size()));
  const GLenum error = gl.GetError();
  drain_gl_errors(gl);
  GLint linked = GL_FALSE;
  if (error == GL_NO_ERROR) gl.GetProgramiv(program, GL_LINK_STATUS, &linked);
  if (error != GL_NO_ERROR || linked != GL_TRUE) {
    gl.DeleteProgram(program);
    refuse(file, error != GL_NO_ERROR ? "the driver refused it (" + std::string(platform::gl_error_name(error)) + ")"
                                      : std::string("the driver did not link it"));
    return 0;
  }
  return program;
}

void ProgramBinaryCache::store(const platform::Gl& gl, GLuint program, const fs::path& file, const ProgramBinaryKey& key) {
  GLint length = 0;
  gl.GetProgramiv(program, GL_PROGRAM_BINARY_LENGTH, &length);
  if (length <= 0) return;  // the driver keeps no binary of this program
  ProgramBinary binary;
  binary.bytes.resize(static_cast<std::size_t>(length));
  GLenum format = 0;
  GLsizei written = 0;
  gl.GetProgramBinary(program, length, &written, &format, binary.bytes.data());
  if (gl.GetError() != GL_NO_ERROR || written <= 0) return drain_gl_errors(gl);
  binary.bytes.resize(static_cast<std::size_t>(written));
  binary.format = format;
  const std::vector<std::uint8_t> encoded = encode_program_binary(key, binary);
  std::error_code ec;
  fs::create_directories(directory_, ec);
  const fs::path temporary = temporary_name(file);
  bool ok = !ec;
  if (ok) {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(encoded.data()), static_cast<std::streamsize>(encoded.size()));
    out.close();
    ok = static_cast<bool>(out);
    if (ok) fs::rename(temporary, file, ec), ok = !ec;
    if (!ok) fs::remove(temporary, ec);
  }
  if (ok) {
    ++counts_.stored;
  } else if (!std::exchange(said_unwritable_, true)) {
    log_ << "program cache: " << directory_.string() << ": cannot store program binaries there"
         << (ec ? " (" + ec.message() + ")" : std::string()) << "; programs are compiled at every start\n";
  }
}

void ProgramBinaryCache::refuse(const fs::path& file, std::string_view why) {
  ++counts_.refused;
  log_ << "program cache: " << file.string() << ": " << why << "; compiling the program instead\n";
}

fs::path default_program_cache_directory(const char* xdg_cache_home, const char* home) {
  if (xdg_cache_home && *xdg_cache_home == '/') return fs::path(xdg_cache_home) / "meter";
  if (home && *home == '/') return fs::path(home) / ".cache" / "meter";
  return {};
}

}  // namespace meter::engine
