# @brief fv_add_subdirs(dir...): add each folder that has a CMakeLists.txt (so a new module needs no edit here).
function(fv_add_subdirs)
  foreach(d ${ARGN})
    if(EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/${d}/CMakeLists.txt)
      add_subdirectory(${d})
    endif()
  endforeach()
endfunction()
