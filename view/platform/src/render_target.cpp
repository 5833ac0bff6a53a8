#include "meter/platform/render_target.hpp"

#include <algorithm>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <utility>

#include "meter/platform/flip_rows.hpp"
#include "shader_resolve.hpp"
#include "meter/protocol/log/logger.hpp"

namespace meter::platform {
namespace {

std::string describe(int w, int h, int samples, bool srgb, DepthFormat depth, SampleFormat samples_in) {
  const char* d = depth == DepthFormat::None ? "no depth"
                  : depth == DepthFormat::Depth24 ? "DEPTH_COMPONENT24" : "DEPTH_COMPONENT32F";
  return std::to_string(w) + "x" + std::to_string(h) + ", " + std::to_string(samples) + " sample(s)" +
         (samples > 1 && samples_in == SampleFormat::Rgba16f ? " in RGBA16F" : "") + ", " +
         (srgb ? "SRGB8_ALPHA8" : "RGBA8") + ", " + d;
}

std::string status_name(GLenum status) {
  switch (status) {
    case GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT: return "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT";
    case GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT: return "GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT";
    case GL_FRAMEBUFFER_UNSUPPORTED: return "GL_FRAMEBUFFER_UNSUPPORTED";
    case GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE: return "GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE";
    default: {
      char buf[32];
      std::snprintf(buf, sizeof buf, "status 0x%04X", status);
      return buf;
    }
  }
}

}  // namespace

RenderTarget::RenderTarget(const GpuBackend& backend, const RenderTargetOptions& options)
    : gl_(&backend.gl()), width_(options.width), height_(options.height), srgb_(options.srgb),
      depth_(options.depth) {
  check_size(backend);
  const bool by_shader = settle_samples(backend, options);
  const GLenum color_format = srgb_ ? GL_SRGB8_ALPHA8 : GL_RGBA8;
  const GLenum depth_format = depth_ == DepthFormat::Depth32F ? GL_DEPTH_COMPONENT32F : GL_DEPTH_COMPONENT24;
  try {
    make_single_sample(color_format, depth_format);
    if (samples_ > 1) make_multisample(color_format, depth_format, by_shader, options.programs);
    gl_->BindRenderbuffer(GL_RENDERBUFFER, 0);
    check_gl(*gl_, "RenderTarget (" + description() + ")");
  } catch (...) {
    release();
    throw;
  }
  bind();
}

void RenderTarget::check_size(const GpuBackend& backend) const {
  const GlInfo& info = gl_->info;
  if (width_ <= 0 || height_ <= 0) {
    throw std::invalid_argument("RenderTarget: size " + std::to_string(width_) + "x" +
                                std::to_string(height_) + " must be positive");
  }
  if (width_ > info.max_texture_size || height_ > info.max_texture_size) {
    throw std::invalid_argument("RenderTarget: size " + std::to_string(width_) + "x" +
                                std::to_string(height_) + " exceeds GL_MAX_TEXTURE_SIZE " +
                                std::to_string(info.max_texture_size) + " of " +
                                std::string(backend.name()));
  }
}

// The samples, resolve filter and sample format this context can give (a downgrade is a warning,
// an impossible request an error). Returns whether a shader pass resolves.
bool RenderTarget::settle_samples(const GpuBackend& backend, const RenderTargetOptions& options) {
  const GlInfo& info = gl_->info;
  const int requested = options.samples;
  if (requested != 1 && requested != 2 && requested != 4 && requested != 8) {
    throw std::invalid_argument("RenderTarget: samples " + std::to_string(requested) +
                                " not supported (expected 1, 2, 4 or 8)");
  }
  samples_ = requested;
  if (samples_ > info.max_samples) {
    samples_ = info.max_samples >= 1 ? info.max_samples : 1;
    warning_ = "RenderTarget: " + std::to_string(requested) + "x MSAA requested but " +
               std::string(backend.name()) + " allows at most GL_MAX_SAMPLES=" +
               std::to_string(info.max_samples) + "; using " + std::to_string(samples_);
    protocol::LogLine(protocol::LogLevel::Warning, "render") << "warning: " << warning_;
  }

  resolve_ = options.resolve;
  if (resolve_.kind != ResolveFilter::Kind::Box) {
    if (!(resolve_.width_px >= ResolveFilter::kMinWidthPx && resolve_.width_px <= ResolveFilter::kMaxWidthPx)) {
      throw std::invalid_argument("RenderTarget: " + std::string(to_string(resolve_.kind)) + " resolve width " +
                                  std::to_string(resolve_.width_px) + " px outside " +
                                  std::to_string(ResolveFilter::kMinWidthPx) + " .. " +
                                  std::to_string(ResolveFilter::kMaxWidthPx) + " px");
    }
    if (samples_ == 1) {
      if (!warning_.empty()) warning_ += "; ";
      warning_ += std::string("RenderTarget: the ") + to_string(resolve_.kind) +
                  " resolve filters MSAA samples; with 1 sample per pixel there is nothing to resolve";
      resolve_ = ResolveFilter{};
    }
  }
  sample_format_ = options.sample_format;
  if (sample_format_ == SampleFormat::Rgba16f && samples_ == 1) {
    if (!warning_.empty()) warning_ += "; ";
    warning_ += "RenderTarget: RGBA16F samples asked for with 1 sample per pixel: there are no samples to keep";
    sample_format_ = SampleFormat::Srgb8;
  }
  // The film filter reads each sample of a neighbourhood, and float samples cannot be blitted into
  // the 8-bit target: both need the samples read one by one by the shader pass.
  const bool reads_samples =
      samples_ > 1 && (resolve_.kind != ResolveFilter::Kind::Box || sample_format_ == SampleFormat::Rgba16f);
  if (reads_samples && !info.has_multisample_texture) {
    const std::string what = resolve_.kind != ResolveFilter::Kind::Box
                                 ? "the " + std::string(to_string(resolve_.kind)) + " resolve needs"
                                 : std::string("RGBA16F samples need");
    throw GlError("RenderTarget: " + what + " multisample textures read per sample (glTexStorage2DMultisample, " +
                  "glGetMultisamplefv, GLSL ES 3.10 sampler2DMS: GLES 3.1 or desktop GL 4.5); " +
                  std::string(backend.name()) + " has " + info.version);
  }
  // A shader pass resolves wherever the samples can be read one by one, the box as well: llvmpipe
  // runs each glBlitFramebuffer as a rasterizer pass of its own, with a fixed cost (0.05-0.2 ms of
  // CPU, meter_readback_bench), where the shader pass draws every region in one pass, to the same
  // bytes. The box is a blit without multisample textures, or when asked (the benchmarks' baseline).
  return reads_samples || (samples_ > 1 && info.has_multisample_texture && !options.box_resolve_by_blit);
}

// Single-sample framebuffer: the resolve destination (and the draw target without MSAA).
void RenderTarget::make_single_sample(GLenum color_format, GLenum depth_format) {
  const Gl& gl = *gl_;
  gl.GenTextures(1, &color_tex_);
  gl.BindTexture(GL_TEXTURE_2D, color_tex_);
  gl.TexStorage2D(GL_TEXTURE_2D, 1, color_format, width_, height_);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  gl.BindTexture(GL_TEXTURE_2D, 0);
  gl.GenFramebuffers(1, &fbo_);
  gl.BindFramebuffer(GL_FRAMEBUFFER, fbo_);
  gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color_tex_, 0);
  if (samples_ == 1 && depth_ != DepthFormat::None) {
    gl.GenRenderbuffers(1, &depth_rb_);
    gl.BindRenderbuffer(GL_RENDERBUFFER, depth_rb_);
    gl.RenderbufferStorage(GL_RENDERBUFFER, depth_format, width_, height_);
    gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_rb_);
  }
  const GLenum status = gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    throw GlError("RenderTarget (" + describe(width_, height_, 1, srgb_, depth_, SampleFormat::Srgb8) +
                  "): framebuffer incomplete: " + status_name(status));
  }
}

void RenderTarget::make_multisample(GLenum color_format, GLenum depth_format, bool by_shader, ProgramCache* programs) {
  const Gl& gl = *gl_;
  gl.GenFramebuffers(1, &msaa_fbo_);
  if (by_shader) {
    // A texture, so the resolve pass can read each sample. Fixed sample locations: required
    // beside a renderbuffer depth attachment, and the filter's weights assume them.
    gl.GenTextures(1, &msaa_color_tex_);
    gl.BindTexture(GL_TEXTURE_2D_MULTISAMPLE, msaa_color_tex_);
    gl.TexStorage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, samples_,
                               sample_format_ == SampleFormat::Rgba16f ? GL_RGBA16F : color_format, width_, height_,
                               GL_TRUE);
    gl.BindTexture(GL_TEXTURE_2D_MULTISAMPLE, 0);
    gl.BindFramebuffer(GL_FRAMEBUFFER, msaa_fbo_);
    gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D_MULTISAMPLE, msaa_color_tex_, 0);
  } else {
    gl.GenRenderbuffers(1, &msaa_color_rb_);
    gl.BindRenderbuffer(GL_RENDERBUFFER, msaa_color_rb_);
    gl.RenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, color_format, width_, height_);
    gl.BindFramebuffer(GL_FRAMEBUFFER, msaa_fbo_);
    gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, msaa_color_rb_);
  }
  if (depth_ != DepthFormat::None) {
    gl.GenRenderbuffers(1, &msaa_depth_rb_);
    gl.BindRenderbuffer(GL_RENDERBUFFER, msaa_depth_rb_);
    gl.RenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, depth_format, width_, height_);
    gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, msaa_depth_rb_);
  }
  const GLenum status = gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    throw GlError("RenderTarget (" + description() +
                  "): multisample framebuffer incomplete: " + status_name(status));
  }
  if (by_shader) shader_resolve_ = std::make_unique<ShaderResolve>(gl, resolve_, samples_, msaa_fbo_, programs);
}

RenderTarget::~RenderTarget() { release(); }

RenderTarget::RenderTarget(RenderTarget&& other) noexcept { *this = std::move(other); }

RenderTarget& RenderTarget::operator=(RenderTarget&& other) noexcept {
  if (this != &other) {
    release();
    gl_ = std::exchange(other.gl_, nullptr);
    width_ = other.width_;
    height_ = other.height_;
    samples_ = other.samples_;
    srgb_ = other.srgb_;
    depth_ = other.depth_;
    sample_format_ = other.sample_format_;
    fbo_ = std::exchange(other.fbo_, 0);
    color_tex_ = std::exchange(other.color_tex_, 0);
    depth_rb_ = std::exchange(other.depth_rb_, 0);
    msaa_fbo_ = std::exchange(other.msaa_fbo_, 0);
    msaa_color_rb_ = std::exchange(other.msaa_color_rb_, 0);
    msaa_depth_rb_ = std::exchange(other.msaa_depth_rb_, 0);
    msaa_color_tex_ = std::exchange(other.msaa_color_tex_, 0);
    resolve_ = other.resolve_;
    shader_resolve_ = std::move(other.shader_resolve_);
    warning_ = std::move(other.warning_);
  }
  return *this;
}

void RenderTarget::release() noexcept {
  if (!gl_) return;
  const Gl& gl = *gl_;
  shader_resolve_.reset();
  if (msaa_color_tex_) gl.DeleteTextures(1, &msaa_color_tex_);
  msaa_color_tex_ = 0;
  if (fbo_) gl.DeleteFramebuffers(1, &fbo_);
  if (msaa_fbo_) gl.DeleteFramebuffers(1, &msaa_fbo_);
  if (color_tex_) gl.DeleteTextures(1, &color_tex_);
  if (depth_rb_) gl.DeleteRenderbuffers(1, &depth_rb_);
  if (msaa_color_rb_) gl.DeleteRenderbuffers(1, &msaa_color_rb_);
  if (msaa_depth_rb_) gl.DeleteRenderbuffers(1, &msaa_depth_rb_);
  fbo_ = msaa_fbo_ = color_tex_ = depth_rb_ = msaa_color_rb_ = msaa_depth_rb_ = 0;
  gl_ = nullptr;
}

void RenderTarget::bind() {
  if (!gl_) throw std::logic_error("RenderTarget::bind on a moved-from target");
  const Gl& gl = *gl_;
  gl.BindFramebuffer(GL_FRAMEBUFFER, draw_framebuffer());
  gl.Viewport(0, 0, width_, height_);
  // Desktop GL only encodes into sRGB attachments when asked; GLES always does.
  if (gl.info.needs_framebuffer_srgb_enable) {
    if (srgb_) gl.Enable(GL_FRAMEBUFFER_SRGB);
    else gl.Disable(GL_FRAMEBUFFER_SRGB);
  }
}

Image RenderTarget::resolve_and_read() {
  const PixelRegion all{0, 0, width_, height_};
  resolve(std::span<const PixelRegion>(&all, 1));
  return read_resolved();
}

void RenderTarget::resolve(std::span<const PixelRegion> regions) {
  if (!gl_) throw std::logic_error("RenderTarget::resolve on a moved-from target");
  if (samples_ <= 1) return;
  const Gl& gl = *gl_;
  if (gl.info.needs_framebuffer_srgb_enable && srgb_) {
    // With GL_FRAMEBUFFER_SRGB on, desktop GL resolves sRGB samples in linear space, as GLES does.
    gl.Enable(GL_FRAMEBUFFER_SRGB);
  }
  // The scissor test clips blits too; a partial redraw leaves it enabled for its last region.
  gl.Disable(GL_SCISSOR_TEST);
  if (shader_resolve_) {
    shader_resolve_->run(msaa_color_tex_, fbo_, width_, height_, regions);
  } else {
    gl.BindFramebuffer(GL_READ_FRAMEBUFFER, msaa_fbo_);
    gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo_);
    for (const PixelRegion& region : regions) {
      const PixelRegion r = clip(region, width_, height_);
      if (r.empty()) continue;
      gl.BlitFramebuffer(r.x, r.y, r.x + r.width, r.y + r.height, r.x, r.y, r.x + r.width, r.y + r.height,
                         GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
  }
  gl.BindFramebuffer(GL_FRAMEBUFFER, draw_framebuffer());
  check_gl(gl, "RenderTarget::resolve (" + description() + ")");
}

void RenderTarget::copy_from(const RenderTarget& source, std::span<const PixelRegion> regions) {
  if (!gl_ || !source.gl_) throw std::logic_error("RenderTarget::copy_from with a moved-from target");
  const Gl& gl = *gl_;
  if (!gl.CopyImageSubData) {
    throw std::invalid_argument("RenderTarget::copy_from: " + gl.info.version +
                                " has no glCopyImageSubData (GLES 3.2, GL 4.3 or EXT/OES_copy_image)");
  }
  if (source.width_ != width_ || source.height_ != height_ || source.samples_ != samples_ ||
      source.srgb_ != srgb_ || source.depth_ != depth_ || source.sample_format_ != sample_format_) {
    throw std::invalid_argument("RenderTarget::copy_from: source " +
                                source.description() +
                                " differs from target " + description());
  }
  // Single-sample targets draw into a colour texture; multisample ones into a multisample texture
  // (shader-pass resolve) or a renderbuffer (blit; copies between the two kinds are allowed).
  const bool ms = samples_ > 1;
  auto colour = [ms](const RenderTarget& t) -> std::pair<GLuint, GLenum> {
    if (!ms) return {t.color_tex_, GL_TEXTURE_2D};
    if (t.msaa_color_tex_) return {t.msaa_color_tex_, GL_TEXTURE_2D_MULTISAMPLE};
    return {t.msaa_color_rb_, GL_RENDERBUFFER};
  };
  const auto [src_color, src_color_target] = colour(source);
  const auto [dst_color, dst_color_target] = colour(*this);
  const GLuint src_depth = ms ? source.msaa_depth_rb_ : source.depth_rb_, dst_depth = ms ? msaa_depth_rb_ : depth_rb_;
  for (const PixelRegion& region : regions) {
    const PixelRegion r = clip(region, width_, height_);
    if (r.empty()) continue;
    gl.CopyImageSubData(src_color, src_color_target, 0, r.x, r.y, 0, dst_color, dst_color_target, 0, r.x, r.y, 0, r.width,
                        r.height, 1);
    if (depth_ != DepthFormat::None)
      gl.CopyImageSubData(src_depth, GL_RENDERBUFFER, 0, r.x, r.y, 0, dst_depth, GL_RENDERBUFFER, 0, r.x, r.y, 0,
                          r.width, r.height, 1);
  }
  check_gl(gl, "RenderTarget::copy_from (" + description() + ")");
}

std::string RenderTarget::description() const {
  return describe(width_, height_, samples_, srgb_, depth_, sample_format_);
}

int RenderTarget::resolve_margin_px() const { return shader_resolve_ ? shader_resolve_->reach() : 0; }

Image RenderTarget::read_resolved() {
  if (!gl_) throw std::logic_error("RenderTarget::read_resolved on a moved-from target");
  const Gl& gl = *gl_;
  gl.BindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
  gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
  Image image(width_, height_);
  gl.ReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
  gl.BindFramebuffer(GL_FRAMEBUFFER, draw_framebuffer());
  check_gl(gl, "RenderTarget::read_resolved (" + description() + ")");
  flip_rows(image);  // GL rows are bottom-up; Image rows are top-down
  return image;
}

std::vector<Image> RenderTarget::read_regions(std::span<const PixelRegion> regions) {
  if (!gl_) throw std::logic_error("RenderTarget::read_regions on a moved-from target");
  if (!regions.empty()) resolve(regions);
  return read_resolved_regions(regions);
}

std::vector<Image> RenderTarget::read_resolved_regions(std::span<const PixelRegion> regions) {
  if (!gl_) throw std::logic_error("RenderTarget::read_resolved_regions on a moved-from target");
  std::vector<Image> out(regions.size());
  if (regions.empty()) return out;
  const Gl& gl = *gl_;
  gl.BindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
  gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
  for (std::size_t i = 0; i < regions.size(); ++i) {
    const PixelRegion r = clip(regions[i], width_, height_);
    if (r.empty()) continue;
    Image image;
    image.width = r.width, image.height = r.height;
    image.rgba.resize(static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height) * 4);
    gl.ReadPixels(r.x, r.y, r.width, r.height, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
    flip_rows(image);  // GL rows are bottom-up; Image rows are top-down
    out[i] = std::move(image);
  }
  gl.BindFramebuffer(GL_FRAMEBUFFER, draw_framebuffer());
  check_gl(gl, "RenderTarget::read_regions (" + description() + ")");
  return out;
}

PixelRegion clip(const PixelRegion& r, int width, int height) {
  const int x0 = std::clamp(r.x, 0, width), y0 = std::clamp(r.y, 0, height);
  const int x1 = std::clamp(r.x + r.width, 0, width), y1 = std::clamp(r.y + r.height, 0, height);
  return {x0, y0, std::max(0, x1 - x0), std::max(0, y1 - y0)};
}

double srgb_to_linear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

double linear_to_srgb(double l) {
  return l <= 0.0031308 ? l * 12.92 : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055;
}

int linear_to_srgb8(double linear) {
  if (!(linear >= 0.0)) linear = 0.0;  // also maps NaN to 0 instead of propagating it
  if (linear > 1.0) linear = 1.0;
  return static_cast<int>(std::lround(linear_to_srgb(linear) * 255.0));
}

}  // namespace meter::platform
