#include "meter/platform/gl_api.hpp"

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace meter::platform {
namespace {

std::string gl_string(const Gl& gl, GLenum what) {
  const GLubyte* s = gl.GetString(what);
  return s ? reinterpret_cast<const char*>(s) : std::string();
}

}  // namespace

bool has_extension(const Gl& gl, std::string_view name) {
  GLint count = 0;
  gl.GetIntegerv(GL_NUM_EXTENSIONS, &count);
  for (GLint i = 0; i < count; ++i) {
    const GLubyte* ext = gl.GetStringi(GL_EXTENSIONS, static_cast<GLuint>(i));
    if (ext && name == reinterpret_cast<const char*>(ext)) return true;
  }
  return false;
}

Gl load_gl(GetProcAddress get_proc, std::string_view backend_name, bool is_gles) {
  Gl gl;
  std::vector<std::string> missing;
  auto load = [&](const char* name) -> void* { return get_proc(name); };
#define METER_GL_LOAD_REQUIRED(name, type)                       \
  gl.name = reinterpret_cast<type>(load("gl" #name));           \
  if (!gl.name) missing.emplace_back("gl" #name);
  METER_GL_REQUIRED_FUNCTIONS(METER_GL_LOAD_REQUIRED)
#undef METER_GL_LOAD_REQUIRED
  if (!missing.empty()) {
    std::string msg = std::string(backend_name) + ": the GL implementation lacks " +
                      std::to_string(missing.size()) + " required GLES 3.0 entry point(s):";
    for (const auto& m : missing) msg += " " + m;
    throw GlError(msg);
  }

  GlInfo& info = gl.info;
  info.is_gles = is_gles;
  info.version = gl_string(gl, GL_VERSION);
  info.renderer = gl_string(gl, GL_RENDERER);
  info.vendor = gl_string(gl, GL_VENDOR);
  info.glsl_version = gl_string(gl, GL_SHADING_LANGUAGE_VERSION);
  // GLES: "OpenGL ES 3.2 Mesa ..."; desktop: "4.5 (Core Profile) Mesa ...".
  const char* v = info.version.c_str();
  const char* prefix = "OpenGL ES ";
  if (std::strncmp(v, prefix, std::strlen(prefix)) == 0) v += std::strlen(prefix);
  if (std::sscanf(v, "%d.%d", &info.major, &info.minor) != 2) {
    throw GlError(std::string(backend_name) + ": cannot parse GL_VERSION '" + info.version +
                  "' (expected 'major.minor ...')");
  }
  gl.GetIntegerv(GL_MAX_SAMPLES, &info.max_samples);
  gl.GetIntegerv(GL_MAX_TEXTURE_SIZE, &info.max_texture_size);
  info.needs_framebuffer_srgb_enable = !is_gles;

  // Timer queries: core in desktop GL >= 3.3, an extension on GLES. A non-null pointer alone
  // proves nothing (EGL may hand out dispatch stubs for any name), so the version/extension decides.
  const bool timer_supported = is_gles ? has_extension(gl, "GL_EXT_disjoint_timer_query")
                                       : (info.major > 3 || (info.major == 3 && info.minor >= 3));
  if (timer_supported) {
    const char* suffix = is_gles ? "EXT" : "";
    gl.QueryCounter = reinterpret_cast<PfnQueryCounter>(load((std::string("glQueryCounter") + suffix).c_str()));
    gl.GetQueryObjectui64v = reinterpret_cast<PfnGetQueryObjectui64v>(
        load((std::string("glGetQueryObjectui64v") + suffix).c_str()));
    info.has_timer_query = gl.QueryCounter && gl.GetQueryObjectui64v;
  }
  // Image copies: same rule (version or extension decides, not the pointer).
  const char* copy_suffix = nullptr;
  if (is_gles ? (info.major > 3 || (info.major == 3 && info.minor >= 2)) : (info.major > 4 || (info.major == 4 && info.minor >= 3)))
    copy_suffix = "";
  else if (is_gles && has_extension(gl, "GL_EXT_copy_image"))
    copy_suffix = "EXT";
  else if (is_gles && has_extension(gl, "GL_OES_copy_image"))
    copy_suffix = "OES";
  if (copy_suffix) {
    gl.CopyImageSubData = reinterpret_cast<PfnCopyImageSubData>(load((std::string("glCopyImageSubData") + copy_suffix).c_str()));
    info.has_copy_image = gl.CopyImageSubData != nullptr;
  }
  // Multisample textures and sample positions: GLES 3.1 core; desktop GL 4.3 core (GL 4.5 also
  // compiles GLSL ES 3.10, ARB_ES3_1_compatibility). Version decides, as above.
  if (is_gles ? (info.major > 3 || (info.major == 3 && info.minor >= 1)) : (info.major > 4 || (info.major == 4 && info.minor >= 5))) {
    gl.TexStorage2DMultisample = reinterpret_cast<PfnTexStorage2DMultisample>(load("glTexStorage2DMultisample"));
    gl.GetMultisamplefv = reinterpret_cast<PfnGetMultisamplefv>(load("glGetMultisamplefv"));
    info.has_multisample_texture = gl.TexStorage2DMultisample && gl.GetMultisamplefv;
  }
  // Shader storage barriers: GLES 3.1, desktop GL 4.2.
  if (is_gles ? (info.major > 3 || (info.major == 3 && info.minor >= 1)) : (info.major > 4 || (info.major == 4 && info.minor >= 2)))
    gl.MemoryBarrier = reinterpret_cast<PfnMemoryBarrier>(load("glMemoryBarrier"));
  // Per-sample shading: GLES 3.2 or OES_sample_shading; desktop GL 4.0.
  if (is_gles ? (info.major > 3 || (info.major == 3 && info.minor >= 2)) : info.major >= 4)
    gl.MinSampleShading = reinterpret_cast<PfnMinSampleShading>(load("glMinSampleShading"));
  else if (is_gles && has_extension(gl, "GL_OES_sample_shading"))
    gl.MinSampleShading = reinterpret_cast<PfnMinSampleShading>(load("glMinSampleShadingOES"));
  // Program binaries: GLES 3.0, desktop GL 4.1; a driver may still offer no format.
  if (is_gles || info.major > 4 || (info.major == 4 && info.minor >= 1)) {
    gl.GetProgramBinary = reinterpret_cast<PFNGLGETPROGRAMBINARYPROC>(load("glGetProgramBinary"));
    gl.ProgramBinary = reinterpret_cast<PFNGLPROGRAMBINARYPROC>(load("glProgramBinary"));
    GLint formats = 0;
    gl.GetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS, &formats);
    info.has_program_binary = gl.GetProgramBinary && gl.ProgramBinary && formats > 0;
  }
  while (gl.GetError() != GL_NO_ERROR) {
  }
  return gl;
}

std::string_view gl_error_name(GLenum error) {
  switch (error) {
    case GL_NO_ERROR: return "GL_NO_ERROR";
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    default: return "unknown GL error";
  }
}

void check_gl(const Gl& gl, std::string_view where) {
  std::string errors;
  // Bounded: a lost context can report errors forever.
  for (int i = 0; i < 16; ++i) {
    const GLenum e = gl.GetError();
    if (e == GL_NO_ERROR) break;
    if (!errors.empty()) errors += ", ";
    errors += gl_error_name(e);
    char code[16];
    std::snprintf(code, sizeof code, " (0x%04X)", e);
    errors += code;
  }
  if (!errors.empty()) throw GlError(std::string(where) + ": " + errors);
}

namespace {

GLuint compile_stage(const Gl& gl, GLenum stage, std::string_view source, std::string_view label) {
  const GLuint shader = gl.CreateShader(stage);
  if (shader == 0) throw GlError(std::string(label) + ": glCreateShader failed");
  const GLchar* src = source.data();
  const GLint len = static_cast<GLint>(source.size());
  gl.ShaderSource(shader, 1, &src, &len);
  gl.CompileShader(shader);
  GLint ok = GL_FALSE;
  gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    GLint log_len = 0;
    gl.GetShaderiv(shader, GL_INFO_LOG_LENGTH, &log_len);
    std::string log(static_cast<std::size_t>(log_len > 1 ? log_len : 1), '\0');
    gl.GetShaderInfoLog(shader, static_cast<GLsizei>(log.size()), nullptr, log.data());
    gl.DeleteShader(shader);
    throw GlError(std::string(label) + ": " + (stage == GL_VERTEX_SHADER ? "vertex" : "fragment") +
                  " shader does not compile: " + log.c_str());
  }
  return shader;
}

}  // namespace

GLuint compile_program(const Gl& gl, std::string_view vertex_source,
                       std::string_view fragment_source, std::string_view label) {
  const GLuint vs = compile_stage(gl, GL_VERTEX_SHADER, vertex_source, label);
  GLuint fs = 0;
  try {
    fs = compile_stage(gl, GL_FRAGMENT_SHADER, fragment_source, label);
  } catch (...) {
    gl.DeleteShader(vs);
    throw;
  }
  const GLuint program = gl.CreateProgram();
  gl.AttachShader(program, vs);
  gl.AttachShader(program, fs);
  gl.LinkProgram(program);
  gl.DetachShader(program, vs);
  gl.DetachShader(program, fs);
  gl.DeleteShader(vs);
  gl.DeleteShader(fs);
  GLint ok = GL_FALSE;
  gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    GLint log_len = 0;
    gl.GetProgramiv(program, GL_INFO_LOG_LENGTH, &log_len);
    std::string log(static_cast<std::size_t>(log_len > 1 ? log_len : 1), '\0');
    gl.GetProgramInfoLog(program, static_cast<GLsizei>(log.size()), nullptr, log.data());
    gl.DeleteProgram(program);
    throw GlError(std::string(label) + ": program does not link: " + log.c_str());
  }
  return program;
}

}  // namespace meter::platform
