# meter_add_gtest(<target> LABELS <labels...> SOURCES <files...> LIBS <libs...> [TIMEOUT s])
# Builds a GoogleTest executable and registers each test case with CTest under the given labels
# (unit, integration, vcan, slow) so `ctest -L unit` runs a subset.
function(meter_add_gtest target)
  cmake_parse_arguments(T "" "TIMEOUT" "LABELS;SOURCES;LIBS" ${ARGN})
  if(NOT METER_BUILD_TESTS)
    return()
  endif()
  if(NOT T_TIMEOUT)
    set(T_TIMEOUT 120)
  endif()
  add_executable(${target} ${T_SOURCES})
  target_link_libraries(${target} PRIVATE ${T_LIBS} GTest::gtest GTest::gtest_main GTest::gmock
                        meter_build_flags Threads::Threads)
  target_compile_definitions(${target} PRIVATE
      METER_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
      METER_BINARY_DIR="${PROJECT_BINARY_DIR}"
      METER_SHARED_DIR="${METER_SHARED_DIR}")
  gtest_discover_tests(${target}
      DISCOVERY_TIMEOUT 60
      PROPERTIES LABELS "${T_LABELS}" TIMEOUT ${T_TIMEOUT}
      WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
endfunction()
