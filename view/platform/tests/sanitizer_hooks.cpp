// LeakSanitizer hooks for the GL tests (used only when built with -fsanitize=address; the
// sanitizer runtime looks these weak symbols up, plain builds never call them).
//
// Mesa's OSMesa and EGL drivers keep a few hundred bytes per context alive until process exit
// (framebuffer wrappers allocated in OSMesaMakeCurrent, llvmpipe's JIT-compiled shader state).
// Those are driver-internal and outside this project; without suppressing them every GL test
// would fail under ASan. Our own allocations are still checked: a leak whose stack does not pass
// through a Mesa library is reported as usual.
extern "C" {

const char* __lsan_default_suppressions();
const char* __lsan_default_suppressions() {
  return "leak:libOSMesa.so\n"
         "leak:libEGL_mesa.so\n"
         "leak:libgallium\n"
         "leak:swrast_dri.so\n"
         "leak:libglapi.so\n"
         "leak:libLLVM\n";
}

}  // extern "C"
