// The Wayland side of meter-view's display: the connection, the globals (wl_compositor,
// xdg_wm_base, wp_presentation), one xdg-shell toplevel surface, its frame callbacks and the
// presentation feedback of each commit. No EGL here (wayland_display.cpp).
#pragma once

#include <cstdint>
#include <ctime>
#include <deque>
#include <string>
#include <vector>

#include "meter/platform/display.hpp"

struct wl_display;
struct wl_registry;
struct wl_compositor;
struct wl_surface;
struct wl_callback;
struct xdg_wm_base;
struct xdg_surface;
struct xdg_toplevel;
struct wp_presentation;
struct wp_presentation_feedback;

namespace meter::platform::detail {

class WaylandWindow {
 public:
  // Connects to `socket` (empty: $WAYLAND_DISPLAY), makes the toplevel and waits for its first
  // configure. Throws BackendError naming the socket and what was missing.
  WaylandWindow(const std::string& socket, bool fullscreen, int frame_wait_ms);
  ~WaylandWindow();
  WaylandWindow(const WaylandWindow&) = delete;
  WaylandWindow& operator=(const WaylandWindow&) = delete;

  wl_display* display() const { return display_; }
  wl_surface* surface() const { return surface_; }

  // Before the commit of frame `frame` (the EGL swap): its frame callback and presentation
  // feedback are asked for.
  void before_commit(std::uint64_t frame);
  // Reads events for at most wait_ms; true once the last commit's frame callback came or its wait
  // ran out (frame_wait_ms after the commit). Throws DisplayLost when the compositor is gone.
  bool frame_ready(int wait_ms);
  // Waits for the frame callback of the last commit (until frame_wait_ms after the commit; a later
  // one counts as a stall and the frame is shown anyway). Throws DisplayLost when the compositor is gone.
  void wait_for_frame();
  // Feedback received so far (waiting up to wait_ms for every frame committed to have one).
  std::vector<PresentedFrame> take_presented(int wait_ms);
  // Throws DisplayLost when the connection failed or the toplevel was closed.
  void check_alive(const char* doing);

  std::uint64_t stalls() const { return stalls_; }
  // CLOCK_MONOTONIC when the last commit's frame callback was read (0: none yet).
  std::int64_t last_frame_done_ns() const { return frame_done_ns_; }
  std::string info() const;

  // Event handlers (the listeners in wayland_window.cpp call these).
  void on_global(wl_registry* registry, std::uint32_t name, const char* interface, std::uint32_t version);
  void on_configure(xdg_surface* surface, std::uint32_t serial);
  void on_toplevel_size(std::int32_t width, std::int32_t height);
  void on_close() { closed_ = true; }
  void on_frame_done(wl_callback* callback);
  void on_clock(std::uint32_t clock_id) { clock_id_ = static_cast<clockid_t>(clock_id); }
  void on_presented(struct wp_presentation_feedback* feedback, const PresentedFrame& shown);

 private:
  void connect(bool fullscreen);
  void release() noexcept;
  // One round of events: flush, wait at most timeout_ms for the socket, read, dispatch. Returns
  // false on timeout.
  bool dispatch_once(int timeout_ms, const char* doing);
  std::int64_t to_monotonic(std::int64_t ns) const;
  // What is left of the wait for the last commit's frame callback (negative: overdue).
  int frame_wait_left_ms() const;

  struct Feedback {
    struct wp_presentation_feedback* feedback;
    std::uint64_t frame;
  };

  std::string socket_name_;
  int frame_wait_ms_;
  wl_display* display_ = nullptr;
  wl_registry* registry_ = nullptr;
  wl_compositor* compositor_ = nullptr;
  std::uint32_t compositor_version_ = 0;
  xdg_wm_base* wm_base_ = nullptr;
  wp_presentation* presentation_ = nullptr;
  clockid_t clock_id_ = CLOCK_MONOTONIC;
  wl_surface* surface_ = nullptr;
  xdg_surface* xdg_surface_ = nullptr;
  xdg_toplevel* toplevel_ = nullptr;
  bool configured_ = false, closed_ = false;
  int configured_width_ = 0, configured_height_ = 0;
  wl_callback* frame_callback_ = nullptr;
  std::int64_t committed_ns_ = 0;
  std::int64_t frame_done_ns_ = 0;  // CLOCK_MONOTONIC of the commit whose frame callback is awaited
  std::deque<Feedback> pending_;
  std::vector<PresentedFrame> presented_;
  std::uint64_t stalls_ = 0;
};

}  // namespace meter::platform::detail
