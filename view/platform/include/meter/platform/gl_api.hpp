// The GL function table every view module calls GL through.
//
// Why a table instead of calling gl* directly: one meter-view process links both libOSMesa and
// libGLESv2/libEGL, and both export the same gl* symbols. A direct call would bind to whichever
// library the linker saw first, i.e. possibly to a library whose context is not current (crash or
// silent no-op). Each backend fills this table through its own get_proc_address, so a call always
// reaches the implementation that owns the current context.
//
// <GLES3/gl3.h> is included for types, constants and the PFNGL...PROC typedefs only; the
// prototypes are switched off so nothing can call a gl* symbol by accident.
#pragma once

#ifndef GL_GLES_PROTOTYPES
#define GL_GLES_PROTOTYPES 0
#endif
#include <GLES3/gl3.h>

#include <stdexcept>
#include <string>
#include <string_view>

// Constants the GLES 3.0 header lacks but that both backends accept (same enum values).
#ifndef GL_FRAMEBUFFER_SRGB
#define GL_FRAMEBUFFER_SRGB 0x8DB9  // desktop GL / EXT_sRGB_write_control
#endif
#ifndef GL_TIME_ELAPSED
#define GL_TIME_ELAPSED 0x88BF  // GL 3.3 / EXT_disjoint_timer_query (GL_TIME_ELAPSED_EXT)
#endif
#ifndef GL_TIMESTAMP
#define GL_TIMESTAMP 0x8E28
#endif
#ifndef GL_GPU_DISJOINT
#define GL_GPU_DISJOINT 0x8FBB  // EXT_disjoint_timer_query
#endif
#ifndef GL_DEPTH_COMPONENT32F
#define GL_DEPTH_COMPONENT32F 0x8CAC
#endif
#ifndef GL_TEXTURE_2D_MULTISAMPLE
#define GL_TEXTURE_2D_MULTISAMPLE 0x9100  // GLES 3.1 / GL 3.2
#endif
#ifndef GL_TEXTURE_BINDING_2D_MULTISAMPLE
#define GL_TEXTURE_BINDING_2D_MULTISAMPLE 0x9104
#endif
#ifndef GL_SAMPLE_POSITION
#define GL_SAMPLE_POSITION 0x8E50
#endif
#ifndef GL_SHADER_STORAGE_BUFFER
#define GL_SHADER_STORAGE_BUFFER 0x90D2  // GLES 3.1 / GL 4.3
#endif
#ifndef GL_SAMPLE_SHADING
#define GL_SAMPLE_SHADING 0x8C36  // glMinSampleShading: GLES 3.2 / GL 4.0 (OES / ARB_sample_shading)
#endif
#ifndef GL_BUFFER_UPDATE_BARRIER_BIT
#define GL_BUFFER_UPDATE_BARRIER_BIT 0x00000200  // glMemoryBarrier: GLES 3.1 / GL 4.2
#endif

namespace meter::platform {

// Ratified GLES 3.0 entry points, required on both backends (desktop GL 4.5 core has all of them).
// X(Name, PFN-typedef) -> member `Name` (gl.Clear(...), gl.UniformMatrix4fv(...)).
#define METER_GL_REQUIRED_FUNCTIONS(X)                                           \
  /* errors, strings, state queries */                                           \
  X(GetError, PFNGLGETERRORPROC)                                                 \
  X(GetString, PFNGLGETSTRINGPROC)                                               \
  X(GetStringi, PFNGLGETSTRINGIPROC)                                             \
  X(GetIntegerv, PFNGLGETINTEGERVPROC)                                           \
  X(GetFloatv, PFNGLGETFLOATVPROC)                                               \
  X(GetInternalformativ, PFNGLGETINTERNALFORMATIVPROC)                           \
  X(Finish, PFNGLFINISHPROC)                                                     \
  X(Flush, PFNGLFLUSHPROC)                                                       \
  X(PixelStorei, PFNGLPIXELSTOREIPROC)                                           \
  X(ReadPixels, PFNGLREADPIXELSPROC)                                             \
  X(ReadBuffer, PFNGLREADBUFFERPROC)                                             \
  X(DrawBuffers, PFNGLDRAWBUFFERSPROC)                                           \
  /* fixed-function state */                                                     \
  X(Enable, PFNGLENABLEPROC)                                                     \
  X(Disable, PFNGLDISABLEPROC)                                                   \
  X(IsEnabled, PFNGLISENABLEDPROC)                                               \
  X(Viewport, PFNGLVIEWPORTPROC)                                                 \
  X(Scissor, PFNGLSCISSORPROC)                                                   \
  X(ClearColor, PFNGLCLEARCOLORPROC)                                             \
  X(ClearDepthf, PFNGLCLEARDEPTHFPROC)                                           \
  X(ClearStencil, PFNGLCLEARSTENCILPROC)                                         \
  X(Clear, PFNGLCLEARPROC)                                                       \
  X(ClearBufferfv, PFNGLCLEARBUFFERFVPROC)                                       \
  X(ClearBufferfi, PFNGLCLEARBUFFERFIPROC)                                       \
  X(ColorMask, PFNGLCOLORMASKPROC)                                               \
  X(DepthMask, PFNGLDEPTHMASKPROC)                                               \
  X(DepthFunc, PFNGLDEPTHFUNCPROC)                                               \
  X(DepthRangef, PFNGLDEPTHRANGEFPROC)                                           \
  X(PolygonOffset, PFNGLPOLYGONOFFSETPROC)                                       \
  X(CullFace, PFNGLCULLFACEPROC)                                                 \
  X(FrontFace, PFNGLFRONTFACEPROC)                                               \
  X(BlendFunc, PFNGLBLENDFUNCPROC)                                               \
  X(BlendFuncSeparate, PFNGLBLENDFUNCSEPARATEPROC)                               \
  X(BlendEquation, PFNGLBLENDEQUATIONPROC)                                       \
  X(BlendEquationSeparate, PFNGLBLENDEQUATIONSEPARATEPROC)                       \
  X(BlendColor, PFNGLBLENDCOLORPROC)                                             \
  X(StencilFunc, PFNGLSTENCILFUNCPROC)                                           \
  X(StencilOp, PFNGLSTENCILOPPROC)                                               \
  X(StencilMask, PFNGLSTENCILMASKPROC)                                           \
  /* buffers and vertex arrays */                                                \
  X(GenBuffers, PFNGLGENBUFFERSPROC)                                             \
  X(DeleteBuffers, PFNGLDELETEBUFFERSPROC)                                       \
  X(BindBuffer, PFNGLBINDBUFFERPROC)                                             \
  X(BindBufferBase, PFNGLBINDBUFFERBASEPROC)                                     \
  X(BindBufferRange, PFNGLBINDBUFFERRANGEPROC)                                   \
  X(BufferData, PFNGLBUFFERDATAPROC)                                             \
  X(BufferSubData, PFNGLBUFFERSUBDATAPROC)                                       \
  X(MapBufferRange, PFNGLMAPBUFFERRANGEPROC)                                     \
  X(UnmapBuffer, PFNGLUNMAPBUFFERPROC)                                           \
  X(GenVertexArrays, PFNGLGENVERTEXARRAYSPROC)                                   \
  X(DeleteVertexArrays, PFNGLDELETEVERTEXARRAYSPROC)                             \
  X(BindVertexArray, PFNGLBINDVERTEXARRAYPROC)                                   \
  X(EnableVertexAttribArray, PFNGLENABLEVERTEXATTRIBARRAYPROC)                   \
  X(DisableVertexAttribArray, PFNGLDISABLEVERTEXATTRIBARRAYPROC)                 \
  X(VertexAttribPointer, PFNGLVERTEXATTRIBPOINTERPROC)                           \
  X(VertexAttribIPointer, PFNGLVERTEXATTRIBIPOINTERPROC)                         \
  X(VertexAttribDivisor, PFNGLVERTEXATTRIBDIVISORPROC)                           \
  X(VertexAttrib4f, PFNGLVERTEXATTRIB4FPROC)                                     \
  /* shaders and programs */                                                     \
  X(CreateShader, PFNGLCREATESHADERPROC)                                         \
  X(DeleteShader, PFNGLDELETESHADERPROC)                                         \
  X(ShaderSource, PFNGLSHADERSOURCEPROC)                                         \
  X(CompileShader, PFNGLCOMPILESHADERPROC)                                       \
  X(GetShaderiv, PFNGLGETSHADERIVPROC)                                           \
  X(GetShaderInfoLog, PFNGLGETSHADERINFOLOGPROC)                                 \
  X(CreateProgram, PFNGLCREATEPROGRAMPROC)                                       \
  X(DeleteProgram, PFNGLDELETEPROGRAMPROC)                                       \
  X(AttachShader, PFNGLATTACHSHADERPROC)                                         \
  X(DetachShader, PFNGLDETACHSHADERPROC)                                         \
  X(BindAttribLocation, PFNGLBINDATTRIBLOCATIONPROC)                             \
  X(LinkProgram, PFNGLLINKPROGRAMPROC)                                           \
  X(ValidateProgram, PFNGLVALIDATEPROGRAMPROC)                                   \
  X(GetProgramiv, PFNGLGETPROGRAMIVPROC)                                         \
  X(GetProgramInfoLog, PFNGLGETPROGRAMINFOLOGPROC)                               \
  X(UseProgram, PFNGLUSEPROGRAMPROC)                                             \
  X(IsProgram, PFNGLISPROGRAMPROC)                                               \
  X(GetAttribLocation, PFNGLGETATTRIBLOCATIONPROC)                               \
  X(GetActiveAttrib, PFNGLGETACTIVEATTRIBPROC)                                   \
  X(GetActiveUniform, PFNGLGETACTIVEUNIFORMPROC)                                 \
  X(GetUniformLocation, PFNGLGETUNIFORMLOCATIONPROC)                             \
  X(GetUniformBlockIndex, PFNGLGETUNIFORMBLOCKINDEXPROC)                         \
  X(UniformBlockBinding, PFNGLUNIFORMBLOCKBINDINGPROC)                           \
  /* uniforms (scalars, vectors, arrays, matrix arrays) */                       \
  X(Uniform1i, PFNGLUNIFORM1IPROC)                                               \
  X(Uniform1iv, PFNGLUNIFORM1IVPROC)                                             \
  X(Uniform2i, PFNGLUNIFORM2IPROC)                                               \
  X(Uniform3i, PFNGLUNIFORM3IPROC)                                               \
  X(Uniform4i, PFNGLUNIFORM4IPROC)                                               \
  X(Uniform1f, PFNGLUNIFORM1FPROC)                                               \
  X(Uniform2f, PFNGLUNIFORM2FPROC)                                               \
  X(Uniform3f, PFNGLUNIFORM3FPROC)                                               \
  X(Uniform4f, PFNGLUNIFORM4FPROC)                                               \
  X(Uniform1fv, PFNGLUNIFORM1FVPROC)                                             \
  X(Uniform2fv, PFNGLUNIFORM2FVPROC)                                             \
  X(Uniform3fv, PFNGLUNIFORM3FVPROC)                                             \
  X(Uniform4fv, PFNGLUNIFORM4FVPROC)                                             \
  X(UniformMatrix2fv, PFNGLUNIFORMMATRIX2FVPROC)                                 \
  X(UniformMatrix3fv, PFNGLUNIFORMMATRIX3FVPROC)                                 \
  X(UniformMatrix4fv, PFNGLUNIFORMMATRIX4FVPROC)                                 \
  /* textures and samplers */                                                    \
  X(GenTextures, PFNGLGENTEXTURESPROC)                                           \
  X(DeleteTextures, PFNGLDELETETEXTURESPROC)                                     \
  X(BindTexture, PFNGLBINDTEXTUREPROC)                                           \
  X(ActiveTexture, PFNGLACTIVETEXTUREPROC)                                       \
  X(TexImage2D, PFNGLTEXIMAGE2DPROC)                                             \
  X(TexSubImage2D, PFNGLTEXSUBIMAGE2DPROC)                                       \
  X(TexStorage2D, PFNGLTEXSTORAGE2DPROC)                                         \
  X(TexParameteri, PFNGLTEXPARAMETERIPROC)                                       \
  X(TexParameterf, PFNGLTEXPARAMETERFPROC)                                       \
  X(GenerateMipmap, PFNGLGENERATEMIPMAPPROC)                                     \
  X(GenSamplers, PFNGLGENSAMPLERSPROC)                                           \
  X(DeleteSamplers, PFNGLDELETESAMPLERSPROC)                                     \
  X(BindSampler, PFNGLBINDSAMPLERPROC)                                           \
  X(SamplerParameteri, PFNGLSAMPLERPARAMETERIPROC)                               \
  X(SamplerParameterf, PFNGLSAMPLERPARAMETERFPROC)                               \
  /* framebuffers and renderbuffers (multisample + blit resolve) */             \
  X(GenFramebuffers, PFNGLGENFRAMEBUFFERSPROC)                                   \
  X(DeleteFramebuffers, PFNGLDELETEFRAMEBUFFERSPROC)                             \
  X(BindFramebuffer, PFNGLBINDFRAMEBUFFERPROC)                                   \
  X(CheckFramebufferStatus, PFNGLCHECKFRAMEBUFFERSTATUSPROC)                     \
  X(FramebufferTexture2D, PFNGLFRAMEBUFFERTEXTURE2DPROC)                         \
  X(FramebufferRenderbuffer, PFNGLFRAMEBUFFERRENDERBUFFERPROC)                   \
  X(GenRenderbuffers, PFNGLGENRENDERBUFFERSPROC)                                 \
  X(DeleteRenderbuffers, PFNGLDELETERENDERBUFFERSPROC)                           \
  X(BindRenderbuffer, PFNGLBINDRENDERBUFFERPROC)                                 \
  X(RenderbufferStorage, PFNGLRENDERBUFFERSTORAGEPROC)                           \
  X(RenderbufferStorageMultisample, PFNGLRENDERBUFFERSTORAGEMULTISAMPLEPROC)     \
  X(BlitFramebuffer, PFNGLBLITFRAMEBUFFERPROC)                                   \
  X(InvalidateFramebuffer, PFNGLINVALIDATEFRAMEBUFFERPROC)                       \
  /* draws */                                                                    \
  X(DrawArrays, PFNGLDRAWARRAYSPROC)                                             \
  X(DrawElements, PFNGLDRAWELEMENTSPROC)                                         \
  X(DrawRangeElements, PFNGLDRAWRANGEELEMENTSPROC)                               \
  X(DrawArraysInstanced, PFNGLDRAWARRAYSINSTANCEDPROC)                           \
  X(DrawElementsInstanced, PFNGLDRAWELEMENTSINSTANCEDPROC)                       \
  /* occlusion/any-samples queries and sync (GLES 3.0 core) */                  \
  X(GenQueries, PFNGLGENQUERIESPROC)                                             \
  X(DeleteQueries, PFNGLDELETEQUERIESPROC)                                       \
  X(BeginQuery, PFNGLBEGINQUERYPROC)                                             \
  X(EndQuery, PFNGLENDQUERYPROC)                                                 \
  X(GetQueryObjectuiv, PFNGLGETQUERYOBJECTUIVPROC)                               \
  X(FenceSync, PFNGLFENCESYNCPROC)                                               \
  X(ClientWaitSync, PFNGLCLIENTWAITSYNCPROC)                                     \
  X(DeleteSync, PFNGLDELETESYNCPROC)

// Optional entry points: may be null. GPU timer queries are core on desktop GL 3.3 but only an
// extension on GLES (EXT_disjoint_timer_query, "...EXT" names; the loader tries both).
using PfnQueryCounter = void(GL_APIENTRYP)(GLuint id, GLenum target);
using PfnGetQueryObjectui64v = void(GL_APIENTRYP)(GLuint id, GLenum pname, GLuint64* params);
// Raw texel copy between images of the same format and sample count (GLES 3.2 / desktop GL 4.3
// core; EXT_copy_image or OES_copy_image on older GLES). The only way to copy multisample pixels
// on GLES, where glBlitFramebuffer into a multisample framebuffer is an error.
using PfnCopyImageSubData = void(GL_APIENTRYP)(GLuint src, GLenum src_target, GLint src_level, GLint src_x,
                                               GLint src_y, GLint src_z, GLuint dst, GLenum dst_target,
                                               GLint dst_level, GLint dst_x, GLint dst_y, GLint dst_z,
                                               GLsizei width, GLsizei height, GLsizei depth);
// Multisample textures (GLES 3.1 / desktop GL 4.3 core) and the sample positions of the bound
// draw framebuffer (GLES 3.1 / GL 3.2): a resolve that reads each sample (sampler2DMS) needs both.
using PfnTexStorage2DMultisample = void(GL_APIENTRYP)(GLenum target, GLsizei samples, GLenum internalformat,
                                                      GLsizei width, GLsizei height, GLboolean fixedsamplelocations);
using PfnGetMultisamplefv = void(GL_APIENTRYP)(GLenum pname, GLuint index, GLfloat* val);
// Orders shader storage writes before later reads of the buffer (GLES 3.1 / desktop GL 4.2).
using PfnMemoryBarrier = void(GL_APIENTRYP)(GLbitfield barriers);
// Per-sample shading: with GL_SAMPLE_SHADING enabled and a minimum of 1.0 the fragment shader runs
// once per covered MSAA sample instead of once per pixel (GLES 3.2 / desktop GL 4.0 core;
// OES_sample_shading on older GLES).
using PfnMinSampleShading = void(GL_APIENTRYP)(GLfloat value);
// A linked program's binary out of the driver and back into a program (GLES 3.0 / desktop GL 4.1
// core): the program-binary cache keeps links across runs (meter/engine/gl/program_binary_cache.hpp).
// Usable only where the driver offers a format (GL_NUM_PROGRAM_BINARY_FORMATS > 0).
#define METER_GL_OPTIONAL_FUNCTIONS(X)                 \
  X(QueryCounter, PfnQueryCounter)                     \
  X(GetQueryObjectui64v, PfnGetQueryObjectui64v)       \
  X(CopyImageSubData, PfnCopyImageSubData)             \
  X(TexStorage2DMultisample, PfnTexStorage2DMultisample) \
  X(GetMultisamplefv, PfnGetMultisamplefv)             \
  X(MemoryBarrier, PfnMemoryBarrier)                   \
  X(MinSampleShading, PfnMinSampleShading)           \
  X(GetProgramBinary, PFNGLGETPROGRAMBINARYPROC)       \
  X(ProgramBinary, PFNGLPROGRAMBINARYPROC)

// What kind of GL the table talks to; decides the few places where desktop GL and GLES differ.
struct GlInfo {
  bool is_gles = false;         // true: OpenGL ES context (EGL); false: desktop core (OSMesa)
  int major = 0;                // context version, parsed from GL_VERSION
  int minor = 0;
  int max_samples = 1;          // GL_MAX_SAMPLES
  int max_texture_size = 0;     // GL_MAX_TEXTURE_SIZE
  bool has_timer_query = false; // GL_TIME_ELAPSED queries usable (QueryCounter/GetQueryObjectui64v)
  bool has_copy_image = false;  // CopyImageSubData usable (RenderTarget::copy_from)
  // TexStorage2DMultisample, GetMultisamplefv and GLSL ES 3.10's sampler2DMS usable (the film
  // filter resolve, resolve_filter.hpp)
  bool has_multisample_texture = false;
  // GetProgramBinary and ProgramBinary usable and at least one binary format offered (Mesa offers
  // one while its shader cache is not switched off: MESA_SHADER_CACHE_DISABLE gives none)
  bool has_program_binary = false;
  // Desktop GL encodes into sRGB attachments only with glEnable(GL_FRAMEBUFFER_SRGB); on GLES the
  // encode is always on. RenderTarget::bind() enables it when this is true.
  bool needs_framebuffer_srgb_enable = false;
  std::string version;          // GL_VERSION
  std::string renderer;         // GL_RENDERER
  std::string vendor;           // GL_VENDOR
  std::string glsl_version;     // GL_SHADING_LANGUAGE_VERSION
};

struct Gl {
#define METER_GL_MEMBER(name, type) type name = nullptr;
  METER_GL_REQUIRED_FUNCTIONS(METER_GL_MEMBER)
  METER_GL_OPTIONAL_FUNCTIONS(METER_GL_MEMBER)
#undef METER_GL_MEMBER
  GlInfo info;
};

// Resolves one entry point by name ("glClear"); returns null when unknown.
using GetProcAddress = void* (*)(const char* name);

// Whether the current context lists the extension `name` (GL_NUM_EXTENSIONS / glGetStringi).
bool has_extension(const Gl& gl, std::string_view name);

// Fills every entry of the table with `get_proc` (the context must be current) and then queries
// GlInfo. Throws GlError naming every missing required function and the backend.
Gl load_gl(GetProcAddress get_proc, std::string_view backend_name, bool is_gles);

class GlError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Name of a GL error code ("GL_INVALID_OPERATION").
std::string_view gl_error_name(GLenum error);

// Throws GlError "<where>: GL_INVALID_ENUM ..." if glGetError reports anything (drains all errors).
void check_gl(const Gl& gl, std::string_view where);

// Compiles and links a vertex + fragment program. On failure throws GlError with `label`, the stage
// and the driver's info log. Returns the program name (shaders are deleted after linking).
GLuint compile_program(const Gl& gl, std::string_view vertex_source,
                       std::string_view fragment_source, std::string_view label);

}  // namespace meter::platform
