#include "wayland/wayland_window.hpp"

#include <poll.h>

#include <cerrno>
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <utility>

#include <wayland-client.h>

#include "presentation-time-client-protocol.h"
#include "xdg-shell-client-protocol.h"

namespace meter::platform::detail {
namespace {

WaylandWindow* window_of(void* data) { return static_cast<WaylandWindow*>(data); }

void registry_global(void* data, wl_registry* registry, std::uint32_t name, const char* interface,
                     std::uint32_t version) {
  window_of(data)->on_global(registry, name, interface, version);
}
void registry_global_remove(void*, wl_registry*, std::uint32_t) {}
const wl_registry_listener kRegistryListener{registry_global, registry_global_remove};

void wm_base_ping(void*, xdg_wm_base* base, std::uint32_t serial) { xdg_wm_base_pong(base, serial); }
const xdg_wm_base_listener kWmBaseListener{wm_base_ping};

void surface_configure(void* data, xdg_surface* surface, std::uint32_t serial) {
  window_of(data)->on_configure(surface, serial);
}
const xdg_surface_listener kXdgSurfaceListener{surface_configure};

void toplevel_configure(void* data, xdg_toplevel*, std::int32_t width, std::int32_t height, wl_array*) {
  window_of(data)->on_toplevel_size(width, height);
}
void toplevel_close(void* data, xdg_toplevel*) { window_of(data)->on_close(); }
void toplevel_bounds(void*, xdg_toplevel*, std::int32_t, std::int32_t) {}
void toplevel_capabilities(void*, xdg_toplevel*, wl_array*) {}
const xdg_toplevel_listener kToplevelListener{toplevel_configure, toplevel_close, toplevel_bounds,
                                              toplevel_capabilities};

void frame_done(void* data, wl_callback* callback, std::uint32_t) { window_of(data)->on_frame_done(callback); }
const wl_callback_listener kFrameListener{frame_done};

void presentation_clock(void* data, wp_presentation*, std::uint32_t clock_id) { window_of(data)->on_clock(clock_id); }
const wp_presentation_listener kPresentationListener{presentation_clock};

void feedback_sync_output(void*, struct wp_presentation_feedback*, wl_output*) {}
void feedback_presented(void* data, struct wp_presentation_feedback* feedback, std::uint32_t sec_hi,
                        std::uint32_t sec_lo, std::uint32_t nsec, std::uint32_t refresh,
                        std::uint32_t seq_hi, std::uint32_t seq_lo, std::uint32_t flags) {
  PresentedFrame shown;
  const std::int64_t sec = static_cast<std::int64_t>((std::uint64_t(sec_hi) << 32) | sec_lo);
  shown.presented_ns = sec * 1'000'000'000 + nsec;
  shown.refresh_ns = refresh;
  shown.sequence = (std::uint64_t(seq_hi) << 32) | seq_lo;
  shown.flags = flags;
  window_of(data)->on_presented(feedback, shown);
}
void feedback_discarded(void* data, struct wp_presentation_feedback* feedback) {
  PresentedFrame gone;
  gone.discarded = true;
  window_of(data)->on_presented(feedback, gone);
}
const wp_presentation_feedback_listener kFeedbackListener{feedback_sync_output, feedback_presented,
                                                          feedback_discarded};

std::int64_t clock_ns(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return std::int64_t(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

}  // namespace

WaylandWindow::WaylandWindow(const std::string& socket, bool fullscreen, int frame_wait_ms)
    : socket_name_(socket), frame_wait_ms_(frame_wait_ms) {
  try {
    connect(fullscreen);
  } catch (...) {
    release();
    throw;
  }
}

void WaylandWindow::connect(bool fullscreen) {
  const std::string socket = socket_name_;
  display_ = wl_display_connect(socket.empty() ? nullptr : socket.c_str());
  if (!display_) {
    const char* env = std::getenv("WAYLAND_DISPLAY");
    const char* dir = std::getenv("XDG_RUNTIME_DIR");
    const std::string tried = socket.empty() ? (env ? env : "wayland-0") : socket;
    throw BackendError("wayland: cannot connect to the compositor at '" + tried + "' (XDG_RUNTIME_DIR=" +
                       (dir ? dir : "unset") + "): " + std::strerror(errno) +
                       "; start one (weston) or name its socket: --output wayland:NAME");
  }
  if (socket_name_.empty()) socket_name_ = std::getenv("WAYLAND_DISPLAY") ? std::getenv("WAYLAND_DISPLAY") : "wayland-0";
  registry_ = wl_display_get_registry(display_);
  wl_registry_add_listener(registry_, &kRegistryListener, this);
  if (wl_display_roundtrip(display_) < 0) check_alive("reading the compositor's globals");
  if (!compositor_ || compositor_version_ < 4 || !wm_base_) {
    const std::string missing = !compositor_ ? "wl_compositor" : compositor_version_ < 4 ? "wl_compositor version 4 (damage_buffer)" : "xdg_wm_base (xdg-shell)";
    throw BackendError("wayland: the compositor at '" + socket_name_ + "' does not offer " + missing);
  }
  if (presentation_) wl_display_roundtrip(display_);  // its clock_id event
  surface_ = wl_compositor_create_surface(compositor_);
  xdg_surface_ = xdg_wm_base_get_xdg_surface(wm_base_, surface_);
  xdg_surface_add_listener(xdg_surface_, &kXdgSurfaceListener, this);
  toplevel_ = xdg_surface_get_toplevel(xdg_surface_);
  xdg_toplevel_add_listener(toplevel_, &kToplevelListener, this);
  xdg_toplevel_set_title(toplevel_, "meter-view");
  xdg_toplevel_set_app_id(toplevel_, "meter-view");
  if (fullscreen) xdg_toplevel_set_fullscreen(toplevel_, nullptr);
  wl_surface_commit(surface_);
  while (!configured_) {
    if (!dispatch_once(frame_wait_ms_ * 5, "waiting for the toplevel's first configure")) {
      throw BackendError("wayland: the compositor at '" + socket_name_ + "' never configured the toplevel");
    }
  }
}

WaylandWindow::~WaylandWindow() { release(); }

void WaylandWindow::release() noexcept {
  for (auto& f : pending_) wp_presentation_feedback_destroy(f.feedback);
  pending_.clear();
  if (frame_callback_) wl_callback_destroy(std::exchange(frame_callback_, nullptr));
  if (toplevel_) xdg_toplevel_destroy(std::exchange(toplevel_, nullptr));
  if (xdg_surface_) xdg_surface_destroy(std::exchange(xdg_surface_, nullptr));
  if (surface_) wl_surface_destroy(std::exchange(surface_, nullptr));
  if (presentation_) wp_presentation_destroy(std::exchange(presentation_, nullptr));
  if (wm_base_) xdg_wm_base_destroy(std::exchange(wm_base_, nullptr));
  if (compositor_) wl_compositor_destroy(std::exchange(compositor_, nullptr));
  if (registry_) wl_registry_destroy(std::exchange(registry_, nullptr));
  if (display_) wl_display_disconnect(std::exchange(display_, nullptr));
}

void WaylandWindow::on_global(wl_registry* registry, std::uint32_t name, const char* interface,
                              std::uint32_t version) {
  const std::string_view what(interface);
  if (what == wl_compositor_interface.name) {
    compositor_version_ = std::min<std::uint32_t>(version, 4);
    compositor_ = static_cast<wl_compositor*>(wl_registry_bind(registry, name, &wl_compositor_interface, compositor_version_));
  } else if (what == xdg_wm_base_interface.name) {
    wm_base_ = static_cast<xdg_wm_base*>(wl_registry_bind(registry, name, &xdg_wm_base_interface, 1));
    xdg_wm_base_add_listener(wm_base_, &kWmBaseListener, this);
  } else if (what == wp_presentation_interface.name) {
    presentation_ = static_cast<wp_presentation*>(wl_registry_bind(registry, name, &wp_presentation_interface, 1));
    wp_presentation_add_listener(presentation_, &kPresentationListener, this);
  }
}

void WaylandWindow::on_configure(xdg_surface* surface, std::uint32_t serial) {
  xdg_surface_ack_configure(surface, serial);
  configured_ = true;
}

void WaylandWindow::on_toplevel_size(std::int32_t width, std::int32_t height) {
  configured_width_ = width;
  configured_height_ = height;
}

void WaylandWindow::on_frame_done(wl_callback* callback) {
  wl_callback_destroy(callback);
  if (callback != frame_callback_) return;
  frame_callback_ = nullptr;
  frame_done_ns_ = clock_ns(CLOCK_MONOTONIC);
}

void WaylandWindow::on_presented(struct wp_presentation_feedback* feedback, const PresentedFrame& shown) {
  for (auto it = pending_.begin(); it != pending_.end(); ++it) {
    if (it->feedback != feedback) continue;
    PresentedFrame f = shown;
    f.frame = it->frame;
    if (!f.discarded) f.presented_ns = to_monotonic(f.presented_ns);
    presented_.push_back(f);
    pending_.erase(it);
    break;
  }
  wp_presentation_feedback_destroy(feedback);
}

std::int64_t WaylandWindow::to_monotonic(std::int64_t ns) const {
  if (clock_id_ == CLOCK_MONOTONIC) return ns;
  return ns - clock_ns(clock_id_) + clock_ns(CLOCK_MONOTONIC);
}

void WaylandWindow::before_commit(std::uint64_t frame) {
  committed_ns_ = clock_ns(CLOCK_MONOTONIC);
  frame_callback_ = wl_surface_frame(surface_);
  wl_callback_add_listener(frame_callback_, &kFrameListener, this);
  if (presentation_) {
    struct wp_presentation_feedback* feedback = wp_presentation_feedback(presentation_, surface_);
    wp_presentation_feedback_add_listener(feedback, &kFeedbackListener, this);
    pending_.push_back({feedback, frame});
  }
}

int WaylandWindow::frame_wait_left_ms() const {
  return frame_wait_ms_ - int((clock_ns(CLOCK_MONOTONIC) - committed_ns_) / 1'000'000);
}

bool WaylandWindow::frame_ready(int wait_ms) {
  if (frame_callback_) dispatch_once(std::clamp(frame_wait_left_ms(), 0, std::max(wait_ms, 0)), "waiting for a frame callback");
  check_alive("waiting for a frame callback");
  return !frame_callback_ || frame_wait_left_ms() <= 0;
}

void WaylandWindow::wait_for_frame() {
  while (frame_callback_) {
    // Events already sent are read even when the wait ran out (a frame that took long to draw).
    const bool read = dispatch_once(std::max(frame_wait_left_ms(), 0), "waiting for a frame callback");
    if (frame_callback_ && !read && frame_wait_left_ms() <= 0) {
      // The compositor stopped repainting this surface: counted, and the next frame goes anyway.
      ++stalls_;
      wl_callback_destroy(std::exchange(frame_callback_, nullptr));
      break;
    }
  }
  check_alive("waiting for a frame callback");
}

std::vector<PresentedFrame> WaylandWindow::take_presented(int wait_ms) {
  const std::int64_t began = clock_ns(CLOCK_MONOTONIC);
  dispatch_once(0, "reading presentation feedback");
  while (!pending_.empty() && wait_ms > 0) {
    const int left = wait_ms - int((clock_ns(CLOCK_MONOTONIC) - began) / 1'000'000);
    if (left <= 0 || !dispatch_once(left, "waiting for presentation feedback")) break;
  }
  return std::exchange(presented_, {});
}

bool WaylandWindow::dispatch_once(int timeout_ms, const char* doing) {
  while (wl_display_prepare_read(display_) != 0) {
    if (wl_display_dispatch_pending(display_) < 0) check_alive(doing);
  }
  if (wl_display_flush(display_) < 0 && errno != EAGAIN) {
    wl_display_cancel_read(display_);
    check_alive(doing);
  }
  pollfd p{wl_display_get_fd(display_), POLLIN, 0};
  const int n = poll(&p, 1, timeout_ms);
  if (n <= 0) {
    wl_display_cancel_read(display_);
    return false;
  }
  if (wl_display_read_events(display_) < 0) check_alive(doing);
  if (wl_display_dispatch_pending(display_) < 0) check_alive(doing);
  return true;
}

void WaylandWindow::check_alive(const char* doing) {
  if (const int error = wl_display_get_error(display_); error != 0) {
    throw DisplayLost(std::string("wayland: the connection to the compositor at '") + socket_name_ + "' failed while " +
                      doing + " (" + std::strerror(error) + "): the compositor went away");
  }
  if (closed_) throw DisplayLost("wayland: the compositor at '" + socket_name_ + "' closed the window while " + doing);
}

std::string WaylandWindow::info() const {
  std::string s = "wayland '" + socket_name_ + "': xdg-shell toplevel";
  if (configured_width_ > 0) s += " configured " + std::to_string(configured_width_) + "x" + std::to_string(configured_height_);
  s += presentation_ ? ", wp_presentation (clock " + std::to_string(int(clock_id_)) + ")" : ", no wp_presentation";
  return s;
}

}  // namespace meter::platform::detail
