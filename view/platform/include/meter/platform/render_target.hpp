// Offscreen render target: framebuffer object of any size with optional MSAA, depth, and sRGB
// encoding, read back as a top-down Image.
//
// Colour handling: the colour attachment is GL_SRGB8_ALPHA8, so shaders write LINEAR colour and GL
// encodes to sRGB on write; blending (and the MSAA resolve) then happen in linear space, as in
// Blender. On GLES the encode is automatic; on desktop GL (OSMesa) bind() enables
// GL_FRAMEBUFFER_SRGB. Example: a shader writing 0.5 stores 188 (sRGB of linear 0.5).
// Set `srgb = false` for data targets (ids, masks) where values must pass through unchanged.
#pragma once

#include "meter/platform/backend.hpp"
#include "meter/platform/gl_api.hpp"
#include "meter/platform/image.hpp"
#include "meter/platform/resolve_filter.hpp"

#include <memory>
#include <span>
#include <string>
#include <vector>

namespace meter::platform {

class ProgramCache;  // program_cache.hpp

// A pixel box in GL window coordinates (origin bottom-left, like glScissor and glBlitFramebuffer).
struct PixelRegion {
  int x = 0, y = 0, width = 0, height = 0;
  bool empty() const { return width <= 0 || height <= 0; }
  bool operator==(const PixelRegion&) const = default;
};

// `r` cut to a width x height target (empty when it lies outside).
PixelRegion clip(const PixelRegion& r, int width, int height);

enum class DepthFormat {
  None,
  // GL_DEPTH_COMPONENT24 (24-bit fixed point, 2^-24 resolution over [0,1] of window depth).
  Depth24,
  // GL_DEPTH_COMPONENT32F (float): use with a reversed-Z projection (near -> 1, far -> 0,
  // glDepthFunc(GL_GREATER), clear depth 0) for much more precision far from the camera; this is
  // what keeps nearly coplanar dial layers (face, ticks, needle) from z-fighting. Depth24 with
  // glPolygonOffset per layer is the alternative.
  Depth32F,
};

// How each MSAA sample's colour is stored until the resolve filters it.
enum class SampleFormat {
  // GL_SRGB8_ALPHA8 (8 bits, sRGB-encoded): a sample holds at most white, so light above 1.0 is
  // clamped before it is filtered, and a thin feature brighter than white loses its share at its
  // edges (a pixel half covered by it resolves to half of white).
  Srgb8,
  // GL_RGBA16F (half float, linear): a sample keeps light above 1.0 until the resolve has filtered
  // it, and the resolved pixel is clamped: the film of a float renderer (Blender EEVEE). Twice the
  // sample memory (8 bytes a sample instead of 4).
  Rgba16f,
};

struct RenderTargetOptions {
  int width = 1280;   // cluster default
  int height = 480;
  // 1 = no MSAA; 2, 4 or 8 samples. Clamped to GL_MAX_SAMPLES (warning on stderr + warning()).
  int samples = 1;
  DepthFormat depth = DepthFormat::Depth24;
  bool srgb = true;
  // How resolve() turns the samples into pixels (resolve_filter.hpp), in a shader pass over a
  // multisample colour texture where GlInfo::has_multisample_texture (GLES 3.1 / GL 4.5). Box: the
  // same bytes as a blit, and a blit without multisample textures. BlackmanHarris: the film filter;
  // needs multisample textures (GlError naming them otherwise) and width_px in ResolveFilter's range
  // (std::invalid_argument). Without MSAA (samples 1) there are no samples to filter: the target
  // then resolves nothing, as a box one, and says so in warning().
  ResolveFilter resolve = {};
  // The box resolve of Srgb8 samples by glBlitFramebuffer of a multisample renderbuffer even where
  // the shader pass exists: the baseline the benchmarks measure the shader pass against.
  bool box_resolve_by_blit = false;
  // The multisample colour storage. Rgba16f is resolved by the shader pass only (a blit cannot
  // filter float samples into the 8-bit target; box_resolve_by_blit does not apply): it needs
  // multisample textures (GlError naming them otherwise). Without MSAA there are no samples: the
  // format is ignored and warning() says so.
  SampleFormat sample_format = SampleFormat::Srgb8;
  // Where the shader-pass resolve gets its program: a cache shared with the targets made before
  // and after this one on the same context (a preview's reloads) links it once. Null: the target
  // links its own. Must outlive the target.
  ProgramCache* programs = nullptr;
};

class ShaderResolve;

// Owns GL objects in the backend's context; the backend must outlive the target and be current.
class RenderTarget {
 public:
  // Throws GlError when the framebuffer is incomplete (names the size/format/samples) and
  // std::invalid_argument for sizes <= 0, sizes above GL_MAX_TEXTURE_SIZE, or samples not in 1,2,4,8.
  RenderTarget(const GpuBackend& backend, const RenderTargetOptions& options);
  ~RenderTarget();
  RenderTarget(const RenderTarget&) = delete;
  RenderTarget& operator=(const RenderTarget&) = delete;
  RenderTarget(RenderTarget&& other) noexcept;
  RenderTarget& operator=(RenderTarget&& other) noexcept;

  // Binds the drawing framebuffer (the multisample one when samples > 1) for draw and read, sets
  // the viewport to the full target, and enables sRGB encoding where the API needs it.
  void bind();
  // Resolves MSAA into the single-sample framebuffer (in linear space for sRGB targets; the box or
  // the film filter, options.resolve), reads RGBA8 and flips rows to top-down. Leaves the drawing
  // framebuffer bound.
  Image resolve_and_read();
  // Resolves only `regions` into the single-sample framebuffer (no-op without MSAA). After a redraw
  // limited to those regions the rest of the resolved image is still current, and an sRGB MSAA
  // resolve costs as much as a full-screen pass on llvmpipe. Regions are clipped to the target. The
  // film filter resolves each region grown by resolve_margin_px(): its pixels that far outside
  // read samples inside, so they change with them.
  void resolve(std::span<const PixelRegion> regions);
  // Reads the single-sample framebuffer (the last resolve) as a top-down RGBA8 image.
  Image read_resolved();
  // Resolves and reads only `regions` (clipped to the target): one top-down RGBA8 image per region,
  // in order, of the clipped size (empty when a region lies outside). An empty list resolves and
  // reads nothing at all. Cheap for a few small boxes: the integrity monitor's readback.
  std::vector<Image> read_regions(std::span<const PixelRegion> regions);
  // The same without the resolve: `regions` of the single-sample framebuffer as the last resolves
  // left it (a caller that tracks what it drew since, resolves just that).
  std::vector<Image> read_resolved_regions(std::span<const PixelRegion> regions);
  // Copies `regions` of the drawing buffers (colour and depth, every sample) of `source` into this
  // target's, unchanged bit for bit: a cached layer restored under a partial redraw. Needs
  // GlInfo::has_copy_image and a source of the same size, samples, colour and depth format
  // (std::invalid_argument otherwise). Regions are clipped to the target; the scissor is ignored.
  void copy_from(const RenderTarget& source, std::span<const PixelRegion> regions);

  int width() const { return width_; }
  int height() const { return height_; }
  int samples() const { return samples_; }  // effective count after clamping
  bool srgb() const { return srgb_; }
  DepthFormat depth() const { return depth_; }
  // The samples' storage in effect (Srgb8 when samples() == 1, whatever was asked).
  SampleFormat sample_format() const { return sample_format_; }
  // The resolve in effect (Box when samples() == 1, whatever was asked).
  const ResolveFilter& resolve_filter() const { return resolve_; }
  // Pixels a resolved pixel reads beyond itself (0 for the box resolve): a change drawn in a
  // region changes the resolved image up to this far outside it.
  int resolve_margin_px() const;
  // Whether resolve() is the shader pass (true) or a glBlitFramebuffer (false; also without MSAA).
  bool resolves_by_shader() const { return shader_resolve_ != nullptr; }
  // The framebuffer draws go to (multisample one when samples() > 1).
  GLuint draw_framebuffer() const { return samples_ > 1 ? msaa_fbo_ : fbo_; }
  // The single-sample framebuffer holding the last resolve (what read_resolved() reads; a caller
  // may read it into a pixel-pack buffer itself).
  GLuint resolved_framebuffer() const { return fbo_; }
  // The single-sample colour texture holding the last resolve (sampleable, e.g. for overlays).
  GLuint color_texture() const { return color_tex_; }
  // Non-empty when the requested options were adjusted (e.g. samples clamped).
  const std::string& warning() const { return warning_; }

 private:
  // The constructor's parts: the size checked against the context; the samples, resolve filter and
  // sample format settled (returns whether a shader pass resolves); the single-sample framebuffer
  // (the resolve destination); the multisample one.
  void check_size(const GpuBackend& backend) const;
  bool settle_samples(const GpuBackend& backend, const RenderTargetOptions& options);
  void make_single_sample(GLenum color_format, GLenum depth_format);
  void make_multisample(GLenum color_format, GLenum depth_format, bool by_shader, ProgramCache* programs);
  void release() noexcept;
  // Size, samples and formats, for messages ("1280x480, 4 sample(s), SRGB8_ALPHA8, ...").
  std::string description() const;

  const Gl* gl_ = nullptr;
  int width_ = 0;
  int height_ = 0;
  int samples_ = 1;
  bool srgb_ = true;
  DepthFormat depth_ = DepthFormat::Depth24;
  SampleFormat sample_format_ = SampleFormat::Srgb8;
  GLuint fbo_ = 0;        // single-sample: colour texture + depth renderbuffer (when samples == 1)
  GLuint color_tex_ = 0;
  GLuint depth_rb_ = 0;
  GLuint msaa_fbo_ = 0;   // multisample: colour texture (shader resolve) or renderbuffer, depth renderbuffer
  GLuint msaa_color_rb_ = 0;
  GLuint msaa_depth_rb_ = 0;
  // Shader-pass resolve: the multisample colour is this texture (msaa_color_rb_ stays 0).
  GLuint msaa_color_tex_ = 0;
  ResolveFilter resolve_;
  std::unique_ptr<ShaderResolve> shader_resolve_;
  std::string warning_;
};

// sRGB transfer functions (IEC 61966-2-1), exact formulas, for tests and CPU-side colour work.
double srgb_to_linear(double encoded);  // 0..1 -> 0..1
double linear_to_srgb(double linear);   // 0..1 -> 0..1
// The 8-bit value a GL sRGB attachment stores for a linear value (round to nearest).
int linear_to_srgb8(double linear);

}  // namespace meter::platform
