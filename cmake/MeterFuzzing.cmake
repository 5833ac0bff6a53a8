# libFuzzer targets (METER_FUZZ=ON, clang only; scripts/fuzz builds and runs them).
#
# meter_add_fuzzer(<name> SOURCES <files...> LIBS <libs...> CORPUS <dir> [DICT <file>] [MAX_LEN <bytes>]
#                  [TIMEOUT <seconds>])
# Builds the executable meter_fuzz_<name> and records, for scripts/fuzz, where its committed seed
# corpus and dictionary live, the largest input worth trying and the time one input may take before
# it counts as a hang (default 1 s; a target that needs more says why beside its call). Adding a reader's target is one
# call beside its library (see controller/fuzz/CMakeLists.txt).
#
# With METER_FUZZ every target of the build gets coverage instrumentation
# (-fsanitize=fuzzer-no-link), or libFuzzer would be blind inside the libraries it drives; only the
# fuzz executables link libFuzzer's main.
if(METER_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "METER_FUZZ=ON needs clang (libFuzzer); configure with CXX=clang++")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link)
  set(METER_FUZZ_MANIFEST_DIR "${PROJECT_BINARY_DIR}/fuzz-targets")
  file(REMOVE_RECURSE "${METER_FUZZ_MANIFEST_DIR}")
  file(MAKE_DIRECTORY "${METER_FUZZ_MANIFEST_DIR}")
endif()

function(meter_add_fuzzer name)
  cmake_parse_arguments(F "" "CORPUS;DICT;MAX_LEN;TIMEOUT" "SOURCES;LIBS" ${ARGN})
  if(NOT METER_FUZZ)
    return()
  endif()
  if(NOT F_CORPUS)
    message(FATAL_ERROR "meter_add_fuzzer(${name}): CORPUS <dir> is required")
  endif()
  if(NOT F_MAX_LEN)
    set(F_MAX_LEN 65536)
  endif()
  if(NOT F_TIMEOUT)
    set(F_TIMEOUT 1)
  endif()
  set(target meter_fuzz_${name})
  add_executable(${target} ${F_SOURCES})
  target_link_libraries(${target} PRIVATE ${F_LIBS} meter_build_flags)
  target_compile_definitions(${target} PRIVATE
      METER_SOURCE_DIR="${PROJECT_SOURCE_DIR}" METER_SHARED_DIR="${METER_SHARED_DIR}")
  target_compile_options(${target} PRIVATE -fsanitize=fuzzer)
  target_link_options(${target} PRIVATE -fsanitize=fuzzer)
  get_filename_component(corpus "${F_CORPUS}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
  set(dict "")
  if(F_DICT)
    get_filename_component(dict "${F_DICT}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
  endif()
  # One shell-sourceable file per target: what scripts/fuzz needs to run it.
  file(WRITE "${METER_FUZZ_MANIFEST_DIR}/${name}"
       "target=${target}\ncorpus=${corpus}\ndict=${dict}\nmax_len=${F_MAX_LEN}\ntimeout=${F_TIMEOUT}\n")
endfunction()
