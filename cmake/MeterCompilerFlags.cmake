# Warnings, sanitizers, and the numerics guard (no -ffast-math anywhere: the numerics tests
# depend on IEEE NaN/Inf semantics and on reproducible rounding).
# Floating-point expressions are evaluated as written, each operation rounded, on every processor: GCC
# otherwise fuses a * b + c into one multiply-add with a single rounding wherever the instruction set
# has one (arm64 always; x86-64 from -march=haswell on), and that moved the last bits of decoded
# values (a DBC's raw * factor + offset, which canmatrix and the x86-64 build round twice) and of the
# renders (docs/targets.md). On x86-64's baseline it changes no instruction.
add_compile_options(-ffp-contract=off)
add_library(meter_build_flags INTERFACE)
target_compile_options(meter_build_flags INTERFACE -Wall -Wextra -Wpedantic)
# GCC 12 reports -Wrestrict inside libstdc++'s std::string operator+ at -O2/-O3 for code that is
# correct (GCC bug 105651, fixed in GCC 13); silence only that warning, only on GCC 12.
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  target_compile_options(meter_build_flags INTERFACE -Wno-restrict)
endif()
if(METER_WERROR)
  target_compile_options(meter_build_flags INTERFACE -Werror)
endif()
if(METER_SANITIZE)
  # -fno-sanitize-recover makes UBSan findings fail the test instead of only printing.
  # -fno-sanitize=vptr: the vptr check emits references to the typeinfo of every polymorphic
  # class it sees, and Debian's glslang is built with -fno-rtti, so glslang::TShader/TProgram
  # have no typeinfo and the shader optimizer would not link under the sanitizers.
  # float-cast-overflow (a double too large for the integer it is converted to) is undefined
  # behaviour that GCC's -fsanitize=undefined leaves out (clang's includes it): asked for by name.
  add_compile_options(-fsanitize=address,undefined,float-cast-overflow -fno-sanitize=vptr
                      -fno-sanitize-recover=undefined,float-cast-overflow -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined,float-cast-overflow)
  # Line tables are all a sanitizer report needs to name file and line; full debug info made the
  # sanitizer build 5.6 GB and its links the slowest step.
  add_compile_options(-g1)
endif()

# The linker: mold (Debian's mold), else LLVM's lld, else GNU ld. lld linked the ~60 test and tool
# programs about 3.5x faster than GNU ld (a 138 MB sanitizer test program: 5.3 s with ld.bfd,
# 1.5 s with ld.lld); mold is faster again and uses every core for one link.
include(CheckLinkerFlag)
check_linker_flag(CXX -fuse-ld=mold METER_HAVE_MOLD)
if(METER_HAVE_MOLD)
  add_link_options(-fuse-ld=mold)
else()
  check_linker_flag(CXX -fuse-ld=lld METER_HAVE_LLD)
  if(METER_HAVE_LLD)
    add_link_options(-fuse-ld=lld)
  endif()
endif()

# ccache when it is installed (scripts install none: every build time the docs quote is measured
# with empty caches). The precompiled GoogleTest header needs ccache's pch sloppiness to be cached.
# (Set through the environment: Debian 12's ccache, 4.7.5, takes no settings on its command line.)
find_program(METER_CCACHE ccache)
if(METER_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  set(_launcher env CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime ${METER_CCACHE})
  set(CMAKE_C_COMPILER_LAUNCHER ${_launcher})
  set(CMAKE_CXX_COMPILER_LAUNCHER ${_launcher})
endif()

# Unity builds: each target's sources compiled in batches of eight, one translation unit a batch, so
# the heavy headers (the standard library, GLM, nlohmann/json, tinygltf, GoogleTest) are parsed once
# a batch instead of once a file. A source whose file-local names would clash with another's in a
# batch is fixed rather than excluded; METER_UNITY=OFF compiles file by file (the meaning is the
# same: the unit tests pass either way).
option(METER_UNITY "Compile each target's sources in unity batches" ON)
if(METER_UNITY)
  set(CMAKE_UNITY_BUILD ON)
  set(CMAKE_UNITY_BUILD_BATCH_SIZE 8)
endif()

foreach(_flags IN ITEMS CMAKE_CXX_FLAGS CMAKE_C_FLAGS CMAKE_CXX_FLAGS_RELEASE CMAKE_CXX_FLAGS_DEBUG
                        CMAKE_CXX_FLAGS_RELWITHDEBINFO CMAKE_EXE_LINKER_FLAGS)
  if("${${_flags}}" MATCHES "fast-math|Ofast|funsafe-math|ffinite-math")
    message(FATAL_ERROR "${_flags} contains '${CMAKE_MATCH_0}': meter forbids fast-math "
                        "(NaN/Inf handling and reproducible numerics are tested). Remove it.")
  endif()
endforeach()
