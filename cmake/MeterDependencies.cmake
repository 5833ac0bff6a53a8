# Every dependency is a Debian 12 package, listed by purpose in scripts/deps/ (scripts/install-deps).
# Each lookup fails at configure time naming the package to install.
find_package(PkgConfig REQUIRED)

function(meter_missing what debpkg)
  message(FATAL_ERROR "meter: ${what} not found. Install the Debian package '${debpkg}' "
                      "(scripts/install-deps build installs what the product needs, scripts/install-deps test the rest).")
endfunction()

# pkg-config module -> imported target PkgConfig::<target>
macro(meter_pkg target module debpkg)
  pkg_check_modules(${target} QUIET IMPORTED_TARGET ${module})
  if(NOT ${target}_FOUND)
    meter_missing("pkg-config module '${module}'" ${debpkg})
  endif()
endmacro()

# find_package(<name> CONFIG) with a named package on failure
macro(meter_config name debpkg)
  find_package(${name} CONFIG QUIET)
  if(NOT ${name}_FOUND)
    meter_missing("CMake package '${name}'" ${debpkg})
  endif()
endmacro()

find_package(Threads REQUIRED)

# protocol/: the authenticated link's MAC, key derivation and nonces (docs/security.md)
meter_pkg(SODIUM libsodium libsodium-dev)

# controller/
meter_pkg(MODBUS libmodbus libmodbus-dev)
meter_config(CLI11 libcli11-dev)
# both processes: sd_notify to the service manager (ready, watchdog keep-alives; docs/deploy.md)
meter_pkg(SYSTEMD libsystemd libsystemd-dev)
# both processes: --log dlt, COVESA DLT through libdlt (docs/logging.md)
meter_pkg(DLT automotive-dlt libdlt-dev)
# What a command-line shell (a program's main: its options, then a call into its library) links:
# CLI11 compiled at -O1. CLI11 is header-only, and optimising its parser at -O3 was about 88 % of
# such a file's compile (clang -ftime-trace: 25.1 of 28.7 s in the back end, 2.3 s parsing);
# the options are parsed once a process start.
add_library(meter_cli INTERFACE)
target_link_libraries(meter_cli INTERFACE CLI11::CLI11)
target_compile_options(meter_cli INTERFACE $<$<CONFIG:Release,RelWithDebInfo>:-O1>)

# view/
meter_config(glm libglm-dev)
meter_config(nlohmann_json nlohmann-json3-dev)
find_path(STB_INCLUDE_DIR stb_image.h PATH_SUFFIXES stb)
if(NOT STB_INCLUDE_DIR)
  meter_missing("stb_image.h" libstb-dev)
endif()
meter_pkg(EGL egl libegl-dev)
meter_pkg(GLESV2 glesv2 libgles-dev)
meter_pkg(OSMESA osmesa libosmesa6-dev)
# meter-view's displays: a Wayland client (--output wayland), its protocols' glue generated from
# wayland-protocols' XML by wayland-scanner at build time ...
meter_pkg(WAYLAND_CLIENT wayland-client libwayland-dev)
meter_pkg(WAYLAND_EGL wayland-egl libwayland-dev)
meter_pkg(WAYLAND_PROTOCOLS wayland-protocols wayland-protocols)
pkg_get_variable(METER_WAYLAND_PROTOCOLS_DIR wayland-protocols pkgdatadir)
find_program(METER_WAYLAND_SCANNER wayland-scanner)
# ... and KMS without a compositor (--output drm): GBM buffers, libdrm's atomic modesetting.
meter_pkg(GBM gbm libgbm-dev)
meter_pkg(DRM libdrm libdrm-dev)
if(NOT METER_WAYLAND_SCANNER)
  meter_missing("wayland-scanner" libwayland-bin)
endif()
find_package(PNG QUIET)
if(NOT PNG_FOUND)
  meter_missing("libpng" libpng-dev)
endif()
find_package(Freetype QUIET)
if(NOT Freetype_FOUND)
  meter_missing("FreeType" libfreetype-dev)
endif()
meter_pkg(LUA lua5.4 liblua5.4-dev)                # scene scripts (PkgConfig::LUA): scene_config checks, engine runs

# The offline side only (meter-convert, never the runtime): glTF loading, mesh tools and the shader
# optimizer, glslang -> spirv-opt -> SPIRV-Cross. A target build (METER_RUNTIME_ONLY) needs none: Debian's
# glslang and SPIRV packages cannot be installed for arm64 beside the host's (docs/targets.md).
if(NOT METER_RUNTIME_ONLY)
  meter_config(TinyGLTF libtinygltf-dev)          # TinyGLTF::TinyGLTF (Debian builds it as a .so)
  meter_config(meshoptimizer libmeshoptimizer-dev) # meshoptimizer::meshoptimizer
  meter_config(glslang glslang-dev)                 # glslang::glslang, glslang::SPIRV
  meter_pkg(SPIRV_TOOLS SPIRV-Tools spirv-tools)
  meter_pkg(SPIRV_CROSS spirv-cross-c-shared libspirv-cross-c-shared-dev)
endif()

# The cluster font: DejaVu Sans from fonts-dejavu-core (a Debian font package, not vendored).
find_file(METER_FONT_FILE DejaVuSans.ttf PATHS /usr/share/fonts/truetype/dejavu NO_DEFAULT_PATH)
if(NOT METER_FONT_FILE)
  meter_missing("DejaVuSans.ttf" fonts-dejavu-core)
endif()
find_file(METER_FONT_BOLD_FILE DejaVuSans-Bold.ttf PATHS /usr/share/fonts/truetype/dejavu NO_DEFAULT_PATH)

# Tests and benchmarks
if(METER_BUILD_TESTS)
  find_package(GTest QUIET)
  if(NOT GTest_FOUND)
    meter_missing("GoogleTest" "libgtest-dev libgmock-dev")
  endif()
  include(GoogleTest)
endif()
if(METER_BUILD_BENCH)
  find_package(benchmark QUIET)
  if(NOT benchmark_FOUND)
    meter_missing("Google Benchmark" libbenchmark-dev)
  endif()
endif()
