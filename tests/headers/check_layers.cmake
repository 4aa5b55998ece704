# @brief The layering check (test_layers): dependencies point down (docs/architecture.md, "Layers"). Run as
#   cmake -DROOT=<source dir> [-DDIRS=<file>] -P check_layers.cmake
# 1. Every `#include "..."` of every .c/.h under a lower room is resolved (beside the including file first, then by
#    path suffix among the tree's headers) and must not land in a room that room may not see.
# 2. DIRS (written at configure time by tests/headers/CMakeLists.txt): one line per target of a lower room, its
#    include directories and linked targets, transitively ("<target>|<room>|dir|<path>",
#    "<target>|<room>|lib|<dep>|<dep's folder>");
#    none may be a folder of a room above it.
# Rules (room: the rooms it may not see): runtime/ (the API, the knobs, gaze, core, app), drivers/ and sim/: render/,
# xr/, tools/; render/: xr/, tools/, drivers/ (render knows no devices); xr/: tools/.
# Every violation is one line naming the file and line (or the target) and the header (or folder); exit 1 if any.
cmake_minimum_required(VERSION 3.20)
if(NOT ROOT)
  message(FATAL_ERROR "check_layers: -DROOT=<source dir> is required")
endif()
get_filename_component(ROOT "${ROOT}" REALPATH)

set(RULE_ROOMS runtime drivers sim render xr)
set(FORBID_runtime render xr tools)
set(FORBID_drivers render xr tools)
set(FORBID_sim render xr tools)
set(FORBID_render xr tools drivers)
set(FORBID_xr tools)

# The room of an absolute path inside ROOT ("" outside every ruled or forbidden room).
function(room_of path out)
  file(RELATIVE_PATH rel "${ROOT}" "${path}")
  string(REGEX MATCH "^[^/]+" top "${rel}")
  set(${out} "${top}" PARENT_SCOPE)
endfunction()

# Every header of the tree (not the build folders, not tests).
file(GLOB_RECURSE all_headers LIST_DIRECTORIES false
  "${ROOT}/runtime/*.h" "${ROOT}/drivers/*.h" "${ROOT}/sim/*.h" "${ROOT}/render/*.h" "${ROOT}/xr/*.h"
  "${ROOT}/tools/*.h")

set(violations 0)
set(scanned 0)
foreach(room ${RULE_ROOMS})
  file(GLOB_RECURSE srcs LIST_DIRECTORIES false "${ROOT}/${room}/*.c" "${ROOT}/${room}/*.h")
  foreach(src ${srcs})
    math(EXPR scanned "${scanned} + 1")
    get_filename_component(dir "${src}" DIRECTORY)
    file(STRINGS "${src}" lines REGEX "^[ \t]*#[ \t]*include[ \t]*\"[^\"]+\"")
    file(RELATIVE_PATH src_rel "${ROOT}" "${src}")
    foreach(line ${lines})
      string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*\"([^\"]+)\".*" "\\1" inc "${line}")
      # Beside the including file (also "../x/y.h") first: that is what the compiler reads first.
      set(hits)
      if(EXISTS "${dir}/${inc}")
        get_filename_component(hit "${dir}/${inc}" REALPATH)
        set(hits "${hit}")
      else()
        string(REGEX REPLACE "([][+.*()^$?|\\\\])" "\\\\\\1" inc_re "${inc}")
        set(hits ${all_headers})
        list(FILTER hits INCLUDE REGEX "/${inc_re}$")
      endif()
      if(NOT hits)
        continue() # a system or generated header
      endif()
      # Allowed when any candidate is in a room this one may see (a lower room's header of the same name wins).
      set(allowed FALSE)
      set(bad)
      foreach(hit ${hits})
        room_of("${hit}" hroom)
        list(FIND FORBID_${room} "${hroom}" idx)
        if(idx EQUAL -1)
          set(allowed TRUE)
        else()
          file(RELATIVE_PATH hrel "${ROOT}" "${hit}")
          list(APPEND bad "${hrel}")
        endif()
      endforeach()
      if(NOT allowed)
        # The line number, for the message.
        file(STRINGS "${src}" all_lines)
        set(n 0)
        set(at 0)
        foreach(l IN LISTS all_lines)
          math(EXPR n "${n} + 1")
          if(l STREQUAL line)
            set(at ${n})
            break()
          endif()
        endforeach()
        list(JOIN bad ", " bad_s)
        list(JOIN FORBID_${room} "/, " forbid_s)
        message("layering: ${src_rel}:${at}: ${room}/ includes \"${inc}\" (${bad_s}): ${room}/ may not see "
                "${forbid_s}/ (docs/architecture.md, Layers)")
        math(EXPR violations "${violations} + 1")
      endif()
    endforeach()
  endforeach()
endforeach()

if(DIRS)
  if(NOT EXISTS "${DIRS}")
    message(FATAL_ERROR "check_layers: ${DIRS}: no such file (configure the build again)")
  endif()
  file(STRINGS "${DIRS}" rows)
  foreach(row ${rows})
    string(REPLACE "|" ";" f "${row}")
    list(GET f 0 tgt)
    list(GET f 1 room)
    list(GET f 2 kind)
    if(kind STREQUAL "dir")
      list(GET f 3 path)
      set(what "include directory ${path}")
    else()
      list(GET f 3 dep)
      list(GET f 4 path)
      set(what "linked target ${dep} (${path})")
    endif()
    if(EXISTS "${path}")
      get_filename_component(path "${path}" REALPATH)
    endif()
    string(FIND "${path}/" "${ROOT}/" pos)
    if(NOT pos EQUAL 0)
      continue() # outside the tree: a system or build folder
    endif()
    room_of("${path}" proom)
    list(FIND FORBID_${room} "${proom}" idx)
    if(NOT idx EQUAL -1)
      list(JOIN FORBID_${room} "/, " forbid_s)
      message("layering: target ${tgt} (${room}/) has the ${what}: ${room}/ may not see ${forbid_s}/ "
              "(docs/architecture.md, Layers)")
      math(EXPR violations "${violations} + 1")
    endif()
  endforeach()
endif()

if(violations GREATER 0)
  message(FATAL_ERROR "check_layers: ${violations} include(s) or target link(s) point up")
endif()
message("check_layers: ${scanned} files, every include points down")
