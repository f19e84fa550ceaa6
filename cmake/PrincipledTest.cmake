# principled_add_gtest(NAME SOURCES src... LIBS lib... [LABELS label...])
# One GTest binary per subsystem. Tests run from the repository root, so fixtures can read
# ../shared/usd-wg exactly as CI lays it out. Labels: "unit" unless given; "long" implies
# "stress"; the default run (scripts/test) excludes "stress".
include(GoogleTest)
function(principled_add_gtest name)
  cmake_parse_arguments(T "" "" "SOURCES;LIBS;LABELS" ${ARGN})
  if(NOT T_LABELS)
    set(T_LABELS unit)
  endif()
  if("long" IN_LIST T_LABELS AND NOT "stress" IN_LIST T_LABELS)
    list(APPEND T_LABELS stress)
  endif()
  add_executable(${name} ${T_SOURCES})
  target_link_libraries(${name} PRIVATE ${T_LIBS} GTest::gtest GTest::gtest_main principled_warnings)
  target_compile_definitions(${name} PRIVATE
    PRINCIPLED_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    PRINCIPLED_BINARY_DIR="${PROJECT_BINARY_DIR}")
  gtest_discover_tests(${name}
    WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
    DISCOVERY_TIMEOUT 60
    TEST_LIST ${name}_TESTS)
  # gtest_discover_tests (CMake 3.25) writes property values unquoted, which splits a list of
  # labels. Set them from a file ctest reads after the discovered test list instead.
  set(labels_file "${CMAKE_CURRENT_BINARY_DIR}/${name}_labels.cmake")
  file(WRITE "${labels_file}"
    "if(${name}_TESTS)\n"
    "  set_tests_properties(\${${name}_TESTS} PROPERTIES LABELS \"${T_LABELS}\")\n"
    "endif()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${labels_file}")
endfunction()
