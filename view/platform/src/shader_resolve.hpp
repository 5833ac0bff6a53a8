// Internal to meter_platform: the MSAA resolve as a shader pass that reads every sample of each
// pixel's neighbourhood from a multisample colour texture (sampler2DMS, texelFetch) and writes their
// weighted mean (resolve_filter.hpp) into a single-sample framebuffer: the film filter's kernel, or
// the box's equal weights of the pixel's own samples (the same bytes as a glBlitFramebuffer resolve,
// in one draw per region of one pass, where llvmpipe runs every blit as a pass of its own).
#pragma once

#include <array>
#include <span>
#include <vector>

#include "meter/platform/gl_api.hpp"
#include "meter/platform/program_cache.hpp"
#include "meter/platform/render_target.hpp"
#include "meter/platform/resolve_filter.hpp"

namespace meter::platform {

class ShaderResolve {
 public:
  // `msaa_fbo` (complete, its colour attachment a `samples`-sample texture) is bound as the draw
  // framebuffer to ask the driver for its sample positions. Throws GlError when the program does not
  // compile or a query fails; the caller has checked GlInfo::has_multisample_texture. The program
  // comes from `programs` when given (it must outlive this), else it is this pass's own.
  ShaderResolve(const Gl& gl, const ResolveFilter& filter, int samples, GLuint msaa_fbo, ProgramCache* programs = nullptr);
  ~ShaderResolve();
  ShaderResolve(const ShaderResolve&) = delete;
  ShaderResolve& operator=(const ShaderResolve&) = delete;

  // Resolves `regions` (clipped to width x height) of `ms_texture` into `dst_fbo`, each grown by
  // reach() pixels: a changed sample changes the resolved pixels that far away. Draws one
  // full-screen triangle per region under a scissor; the GL state it changes (program, vertex
  // array, texture unit 0's multisample binding, blend, depth, stencil, cull, dither) is put back,
  // except the scissor test, which is left off (as the blit resolve leaves it).
  void run(GLuint ms_texture, GLuint dst_fbo, int width, int height, std::span<const PixelRegion> regions) const;

  int reach() const { return reach_; }
  const std::vector<std::array<float, 2>>& sample_positions() const { return positions_; }

 private:
  void release();  // gives back the program, deletes the vertex array

  const Gl& gl_;
  int samples_ = 0, reach_ = 0;
  std::vector<std::array<float, 2>> positions_;
  ProgramCache* programs_ = nullptr;
  GLuint program_ = 0, vao_ = 0;  // the weights are the program's constants
  GLint samples_loc_ = -1;
};

}  // namespace meter::platform
