# Precompiled headers. Most of a translation unit's compile time here is parsing the same third-party headers
# (nlohmann-json with JSON_DIAGNOSTICS, Eigen, fmt; GoogleTest in the tests): CI builds from scratch twice (asan,
# fuzz). They are compiled once, in mb_pch (libraries, commands) and mb_pch_test (tests), and every other C++ target
# reuses one of them (REUSE_FROM): each translation unit then sees these headers included first, which changes
# nothing else (they are self-contained and guarded).
# A target whose flags the precompiled header does not match (the Python module: hidden visibility) keeps its own
# parsing. Only system headers: our own, reached by another path, clash with #pragma once in GCC's PCH. Off with
# -DMB_PCH=OFF (e.g. to check that every file includes what it uses).
option(MB_PCH "Compile the heavy third-party headers once (precompiled headers)" ON)

# ccache caches a compile that uses a precompiled header only with these sloppiness settings (ccache manual,
# "Precompiled headers"): the header's defines and time macros are not hashed, and the just-built .gch is not
# "too new". Without them every compile is uncacheable and rebuilds start from nothing. CCACHE_BASEDIR (paths below
# the source folder hashed as relative ones) and CCACHE_NOHASHDIR (the build folder not hashed into -g compiles) make
# the compile commands of another clone on the same machine — CI's fresh clone — hash alike ("Compiling in different
# directories"). GCC's .gch embeds its build folder and every object's hash includes the .gch's bytes, so a clone
# reuses the objects only when its .gch came from the cache too, i.e. once one whole tree was built with these
# settings. The debug information then names the files relative to the build folder.
if(MB_PCH AND CMAKE_CXX_COMPILER_LAUNCHER MATCHES "ccache$")
  set(CMAKE_CXX_COMPILER_LAUNCHER
      ${CMAKE_COMMAND} -E env CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime
      CCACHE_BASEDIR=${CMAKE_SOURCE_DIR} CCACHE_NOHASHDIR=1 ${CMAKE_CXX_COMPILER_LAUNCHER})
endif()

set(MB_PCH_HEADERS
    <algorithm> <cmath> <functional> <map> <memory> <optional> <stdexcept> <string> <string_view> <utility>
    <vector> <Eigen/Core> <Eigen/Dense> <nlohmann/json.hpp> <fmt/format.h>)

# The libraries whose headers the precompiled headers hold: every target that reuses them links these too (their
# include folders and definitions, e.g. FMT_SHARED, must match).
set(MB_PCH_LIBRARIES Eigen3::Eigen nlohmann_json::nlohmann_json fmt::fmt)

# One precompiled header per kind of target, since GCC uses one only with the same code model: mb_pch (executables
# and libraries built as they are), mb_pch_pic (position-independent libraries: those the Python module links) and
# mb_pch_test (the test executables: GoogleTest too).
function(mb_add_precompiled_headers)
  if(NOT MB_PCH)
    return()
  endif()
  # A precompiled header whose flags do not match is skipped silently: say so instead.
  target_compile_options(mb_warnings INTERFACE -Winvalid-pch)
  file(WRITE ${PROJECT_BINARY_DIR}/mb_pch.cc "// The translation unit the precompiled headers are built with.\n")
  foreach(variant mb_pch mb_pch_pic)
    add_library(${variant} STATIC ${PROJECT_BINARY_DIR}/mb_pch.cc)
    target_link_libraries(${variant} PRIVATE ${MB_PCH_LIBRARIES} mb_options)
    target_precompile_headers(${variant} PRIVATE ${MB_PCH_HEADERS})
  endforeach()
  set_target_properties(mb_pch_pic PROPERTIES POSITION_INDEPENDENT_CODE ON)
  if(MB_BUILD_TESTS)
    add_library(mb_pch_test STATIC ${PROJECT_BINARY_DIR}/mb_pch.cc)
    target_link_libraries(mb_pch_test PRIVATE ${MB_PCH_LIBRARIES} GTest::gtest GTest::gmock mb_options
                          mb_test_options)
    target_precompile_headers(mb_pch_test PRIVATE ${MB_PCH_HEADERS} <gtest/gtest.h> <gmock/gmock.h>)
  endif()
endfunction()

# Every C++ target below `dir` (recursively) into `out`.
function(mb_targets_below dir out)
  get_property(targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
  get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
  foreach(sub ${subdirs})
    mb_targets_below(${sub} below)
    list(APPEND targets ${below})
  endforeach()
  set(${out} ${targets} PARENT_SCOPE)
endfunction()

# Makes every library and executable of the project reuse its kind's precompiled header.
function(mb_reuse_precompiled_headers)
  if(NOT MB_PCH)
    return()
  endif()
  mb_targets_below(${PROJECT_SOURCE_DIR} targets)
  foreach(target ${targets})
    get_target_property(type ${target} TYPE)
    if(NOT type MATCHES "^(STATIC_LIBRARY|OBJECT_LIBRARY|SHARED_LIBRARY|EXECUTABLE)$"
       OR target MATCHES "^mb_pch" OR target STREQUAL "motionblocks_python")
      continue()
    endif()
    get_target_property(sources ${target} SOURCES)
    list(FILTER sources INCLUDE REGEX "\\.cc$")
    if(NOT sources)
      continue()
    endif()
    get_target_property(libraries ${target} LINK_LIBRARIES)
    get_target_property(pic ${target} POSITION_INDEPENDENT_CODE)
    if(libraries MATCHES "GTest::" AND TARGET mb_pch_test)
      set(variant mb_pch_test)
      target_link_libraries(${target} PRIVATE mb_test_options)
    elseif(pic)
      set(variant mb_pch_pic)
    else()
      set(variant mb_pch)
    endif()
    target_link_libraries(${target} PRIVATE ${MB_PCH_LIBRARIES})
    target_precompile_headers(${target} REUSE_FROM ${variant})
  endforeach()
endfunction()
