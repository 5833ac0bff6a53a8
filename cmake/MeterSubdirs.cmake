# meter_add_child_dirs([FIRST dir...]): add every direct child folder that has a CMakeLists.txt, so
# a new bench or integration-test folder joins the build without editing its parent. FIRST names
# folders that define things the others use (e.g. tests/support) and must come before them.
function(meter_add_child_dirs)
  cmake_parse_arguments(A "" "" "FIRST" ${ARGN})
  foreach(child IN LISTS A_FIRST)
    add_subdirectory(${child})
  endforeach()
  file(GLOB children LIST_DIRECTORIES true RELATIVE ${CMAKE_CURRENT_SOURCE_DIR} ${CMAKE_CURRENT_SOURCE_DIR}/*)
  list(SORT children)
  foreach(child IN LISTS children)
    if(child IN_LIST A_FIRST)
      continue()
    endif()
    if(IS_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/${child} AND EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/${child}/CMakeLists.txt)
      add_subdirectory(${child})
    endif()
  endforeach()
endfunction()
