# Precompiled headers for the heavy dependencies (gRPC, protobuf, OpenCV, Eigen, yaml-cpp,
# GoogleTest). Parsing them is most of the compile time of a typical file here, and CI
# builds three trees (release, ASan, TSan) on two cores.
#
# omniview_precompile_headers() runs once, after every target is defined, and gives each
# C++ target the precompiled headers of the dependencies it links (directly or through
# other targets), so no source file needs to know about it:
# - every target reuses the header of a host target made for its set of dependencies and
#   compile options of its own (core's -O3, generated code's -w), so each set is compiled
#   once per tree (a precompiled header costs 10-20 s and 150-350 MB; there are a handful
#   of sets, against ~70 targets). GCC refuses a header made with other macros or
#   code-generation flags (-O0 against -O2, -pthread's _REENTRANT), hence the sets;
# - a target whose libraries a host at the top level could not link (Boost, found in
#   server/web) compiles the header itself for the others of its set, if it has four
#   sources or more; a small target alone with its options goes without;
# - -Werror=invalid-pch makes a header GCC passes over fail the build (it would cost its
#   whole parse in every file of the target); generated code's -w silences it there.
# Only third-party and standard headers go in, so a change to our own headers rebuilds
# exactly what it did before. OMNIVIEW_PCH=OFF builds without (to check that every file
# includes what it uses).
option(OMNIVIEW_PCH "Precompile the headers of heavy dependencies" ON)

set(_omniview_pch_std <algorithm> <chrono> <cstdint> <functional> <map> <memory> <mutex> <optional>
    <string> <thread> <vector>)
# Dependency (a target name in the link closure) -> its headers.
set(_omniview_pch_Eigen3::Eigen <Eigen/Core> <Eigen/Geometry>)
set(_omniview_pch_opencv_core <opencv2/core.hpp>)
set(_omniview_pch_yaml-cpp <yaml-cpp/yaml.h>)
set(_omniview_pch_gRPC::grpc++ <grpcpp/grpcpp.h>)
set(_omniview_pch_GTest::gtest <gtest/gtest.h>)
# Our own API's generated code: the heaviest header of the server and its tests.
set(_omniview_pch_omniview_proto <omniview/v1/omniview.grpc.pb.h>)
# Threads adds -pthread, which defines _REENTRANT: a header precompiled without it is
# refused by a target with it, so it is part of the key (no headers of its own).
set(_omniview_pch_Threads::Threads)
set(_omniview_pch_dependencies Eigen3::Eigen opencv_core yaml-cpp gRPC::grpc++ omniview_proto GTest::gtest
    Threads::Threads)

# Every target name reachable from `target`'s link libraries, into `out`.
function(_omniview_link_closure target out)
  set(seen)
  set(queue ${target})
  while(queue)
    list(POP_FRONT queue item)
    # Generator expressions such as $<LINK_ONLY:x> and $<LINK_LIBRARY:WHOLE_ARCHIVE,x> hide
    # a plain target name.
    string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" item "${item}")
    string(REGEX REPLACE "^\\$<LINK_LIBRARY:[^,]*,(.*)>$" "\\1" item "${item}")
    if(NOT TARGET ${item} OR item IN_LIST seen)
      continue()
    endif()
    list(APPEND seen ${item})
    get_target_property(alias ${item} ALIASED_TARGET)
    if(alias)
      list(APPEND queue ${alias})
    endif()
    foreach(property LINK_LIBRARIES INTERFACE_LINK_LIBRARIES)
      get_target_property(libs ${item} ${property})
      if(libs)
        list(APPEND queue ${libs})
      endif()
    endforeach()
  endwhile()
  # gtest_main brings gtest.
  if(GTest::gtest_main IN_LIST seen)
    list(APPEND seen GTest::gtest)
  endif()
  set(${out} ${seen} PARENT_SCOPE)
endfunction()

# The headers worth precompiling for `target` (empty: none), and a key naming that set.
function(_omniview_pch_headers target headers_out key_out)
  _omniview_link_closure(${target} closure)
  list(REMOVE_ITEM closure ${target})  # omniview_proto's own headers come from its build
  set(headers)
  set(key)
  foreach(dependency IN LISTS _omniview_pch_dependencies)
    if(dependency IN_LIST closure)
      list(APPEND headers ${_omniview_pch_${dependency}})
      string(REGEX REPLACE "[^A-Za-z0-9]" "_" name ${dependency})
      string(APPEND key "_${name}")
    endif()
  endforeach()
  if(headers)
    set(headers ${_omniview_pch_std} ${headers})
  endif()
  set(${headers_out} ${headers} PARENT_SCOPE)
  set(${key_out} ${key} PARENT_SCOPE)
endfunction()

function(omniview_precompile_headers)
  if(NOT OMNIVIEW_PCH OR OMNIVIEW_FUZZ)
    return()
  endif()
  omniview_targets_below(${PROJECT_SOURCE_DIR} targets)
  get_property(project_options DIRECTORY ${PROJECT_SOURCE_DIR} PROPERTY COMPILE_OPTIONS)
  # First the targets worth a header, each with its dependency key and, where it has
  # compile options of its own, a group key of those options; groups are counted so a
  # small target shares a header only with others of its options (generated code: -w).
  set(candidates)
  foreach(target IN LISTS targets)
    get_target_property(type ${target} TYPE)
    if(NOT type MATCHES "^(STATIC_LIBRARY|SHARED_LIBRARY|OBJECT_LIBRARY|EXECUTABLE)$")
      continue()
    endif()
    get_target_property(sources ${target} SOURCES)
    list(FILTER sources INCLUDE REGEX "\\.(cc|cpp|cxx)$")
    list(LENGTH sources source_count)
    if(source_count EQUAL 0)
      continue()
    endif()
    _omniview_pch_headers(${target} headers key)
    if(NOT headers)
      continue()
    endif()
    # Options beyond the project-wide ones (add_compile_options) change the flags.
    get_target_property(options ${target} COMPILE_OPTIONS)
    set(group "-")  # none: the project's options
    if(options AND NOT "${options}" STREQUAL "${project_options}")
      string(MD5 group "${key} ${options}")
      get_property(members GLOBAL PROPERTY _omniview_pch_members_${group})
      math(EXPR members "${members} + 0")
      math(EXPR members "${members} + 1")
      set_property(GLOBAL PROPERTY _omniview_pch_members_${group} ${members})
    endif()
    list(APPEND candidates ${target})
    set_property(GLOBAL PROPERTY _omniview_pch_of_${target} "${key}|${group}|${source_count}|${headers}")
  endforeach()

  foreach(target IN LISTS candidates)
    get_property(entry GLOBAL PROPERTY _omniview_pch_of_${target})
    string(REPLACE "|" ";" entry "${entry}")
    list(POP_FRONT entry key group source_count)
    set(headers ${entry})
    set(own)
    if(NOT group STREQUAL "-")
      get_target_property(own ${target} COMPILE_OPTIONS)
      list(REMOVE_ITEM own ${project_options})
    endif()
    # Targets of the same dependencies and own options (none; generated code's -w; core,
    # cloud and robot's -O3) share one host's header. A host, not the first such target:
    # the targets' own definitions differ (OMNIVIEW_SOURCE_DIR), and GCC refuses a header
    # made with a definition the file lacks.
    _omniview_pch_host_name(${key} "${own}" host)
    _omniview_links_visible_here(${target} visible)
    get_property(members GLOBAL PROPERTY _omniview_pch_members_${group})
    if(TARGET ${host} OR (visible AND (group STREQUAL "-" OR members GREATER_EQUAL 2)))
      _omniview_pch_host(${key} "${headers}" ${target} host OPTIONS ${own})
      target_precompile_headers(${target} REUSE_FROM ${host})
    elseif(source_count GREATER_EQUAL 4)
      # A host made here, at the top level, cannot link packages a target's own folder
      # finds (web's Boost): the first such target compiles the header, the rest reuse it.
      get_property(owner GLOBAL PROPERTY _omniview_pch_owner_${host})
      if(owner)
        target_precompile_headers(${target} REUSE_FROM ${owner})
      else()
        set_property(GLOBAL PROPERTY _omniview_pch_owner_${host} ${target})
        target_precompile_headers(${target} PRIVATE ${headers})
      endif()
    else()
      continue()  # a header of its own would cost more than it saves
    endif()
    target_compile_options(${target} PRIVATE -Werror=invalid-pch)
  endforeach()
endfunction()

# Whether every library `target` links directly is a target (or a flag) seen from here,
# the top level: a host linking them then gets the same include paths and definitions.
function(_omniview_links_visible_here target out)
  get_target_property(libs ${target} LINK_LIBRARIES)
  if(NOT libs)
    set(libs)
  endif()
  foreach(item IN LISTS libs)
    string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" item "${item}")
    string(REGEX REPLACE "^\\$<LINK_LIBRARY:[^,]*,(.*)>$" "\\1" item "${item}")
    if(NOT TARGET "${item}" AND NOT item MATCHES "^-")
      set(${out} FALSE PARENT_SCOPE)
      return()
    endif()
  endforeach()
  set(${out} TRUE PARENT_SCOPE)
endfunction()

# The name of the host target for dependency key `key` and own compile options `options`.
function(_omniview_pch_host_name key options out)
  set(host omniview_pch${key})
  if(options)
    string(MD5 options_hash "${options}")
    string(SUBSTRING ${options_hash} 0 8 options_hash)
    string(APPEND host _options_${options_hash})
  endif()
  set(${out} ${host} PARENT_SCOPE)
endfunction()

# A host target whose only job is to compile the precompiled header for one set of
# dependencies (and OPTIONS, where given), with the default flags; made on first use,
# linking what `example` links so the include paths and definitions match.
function(_omniview_pch_host key headers example out)
  cmake_parse_arguments(PARSE_ARGV 4 arg "" "" "OPTIONS")
  _omniview_pch_host_name(${key} "${arg_OPTIONS}" host)
  if(NOT TARGET ${host})
    set(empty ${PROJECT_BINARY_DIR}/pch/${host}.cc)
    file(WRITE ${empty} "// Compiles the precompiled header of ${host} (cmake/OmniviewPch.cmake).\n")
    add_library(${host} OBJECT ${empty})
    get_target_property(libs ${example} LINK_LIBRARIES)
    target_link_libraries(${host} PRIVATE ${libs})
    target_precompile_headers(${host} PRIVATE ${headers})
    target_compile_options(${host} PRIVATE ${arg_OPTIONS} -Werror=invalid-pch)
  endif()
  set(${out} ${host} PARENT_SCOPE)
endfunction()
