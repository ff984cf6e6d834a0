# Helpers that look at every target once all are defined (the top CMakeLists calls them last).

# The C++ targets defined in `dir` and below, into `out`.
function(omniview_targets_below dir out)
  get_property(targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
  get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
  foreach(subdir IN LISTS subdirs)
    omniview_targets_below(${subdir} below)
    list(APPEND targets ${below})
  endforeach()
  set(${out} ${targets} PARENT_SCOPE)
endfunction()

# `programs`: every program that is not a test (the daemon, the CLI, spot-mock, tools,
# benchmarks), so scripts/test.sh can build them in the release tree without the unit tests
# that only the sanitizer tree runs.
function(omniview_programs_target)
  omniview_targets_below(${PROJECT_SOURCE_DIR} targets)
  add_custom_target(programs)
  foreach(target IN LISTS targets)
    get_target_property(type ${target} TYPE)
    get_target_property(dir ${target} SOURCE_DIR)
    string(FIND "${dir}/" "${PROJECT_SOURCE_DIR}/tests/" tests_at)
    if(type STREQUAL "EXECUTABLE" AND NOT tests_at EQUAL 0)
      add_dependencies(programs ${target})
    endif()
  endforeach()
endfunction()
