# 64-bit ARM (arm64, aarch64) Linux with Debian's cross toolchain (crossbuild-essential-arm64) and the
# :arm64 development packages installed beside the host's through multiarch (scripts/deps/arm64.list,
# `scripts/install-deps arm64`). No sysroot: Debian puts the target's libraries in
# /usr/lib/aarch64-linux-gnu and shares /usr/include. scripts/cross-build arm64 configures with it
# (docs/targets.md).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)
# mold links for arm64 too, but the cross gcc looks for its linker under its own prefix and so does not
# find ld.mold by -fuse-ld=mold: mold's directory of linker names is put first instead.
if(EXISTS /usr/libexec/mold/ld)
  set(CMAKE_EXE_LINKER_FLAGS_INIT -B/usr/libexec/mold)
  set(CMAKE_SHARED_LINKER_FLAGS_INIT -B/usr/libexec/mold)
endif()

# pkg-config reads the target's .pc files (and the architecture-independent ones), never the host's.
set(ENV{PKG_CONFIG_LIBDIR} /usr/lib/aarch64-linux-gnu/pkgconfig:/usr/share/pkgconfig)
set(ENV{PKG_CONFIG_PATH} "")

# Programs run at build time (wayland-scanner) are the host's; libraries and packages the target's.
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)

# The target's programs run on this machine under qemu-user (qemu-user-static), through the arm64
# dynamic loader and libraries multiarch installed (/lib/ld-linux-aarch64.so.1): GoogleTest's test
# discovery and ctest run every test program through it, so no binfmt registration is needed.
# A Mesa shader cache of the target's own: the arm64 llvmpipe (Mesa 22.3.6), which keeps compiled
# machine code in that cache, crashed (SIGSEGV after making its context) in the cache the host's Mesa
# fills (~/.cache/mesa_shader_cache), and does not in a cache of its own.
set(CMAKE_CROSSCOMPILING_EMULATOR env MESA_SHADER_CACHE_DIR=${CMAKE_BINARY_DIR}/mesa-shader-cache qemu-aarch64-static)

# The Debian packages CPack makes are for the target.
set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE arm64)
