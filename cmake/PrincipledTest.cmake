# principled_add_gtest(NAME SOURCES src... LIBS lib... [LABELS label...])
# One GTest binary per subsystem. Tests run from the repository root, so fixtures can read
# ../shared/usd-wg exactly as CI lays it out. The default run excludes the label "stress".
include(GoogleTest)
function(principled_add_gtest name)
  cmake_parse_arguments(T "" "" "SOURCES;LIBS;LABELS" ${ARGN})
  if(NOT T_LABELS)
    set(T_LABELS unit)
  endif()
  add_executable(${name} ${T_SOURCES})
  target_link_libraries(${name} PRIVATE ${T_LIBS} GTest::gtest GTest::gtest_main principled_warnings)
  target_compile_definitions(${name} PRIVATE
    PRINCIPLED_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    PRINCIPLED_BINARY_DIR="${PROJECT_BINARY_DIR}")
  # gtest_discover_tests (CMake 3.25) writes property values unquoted, so a list of labels
  # would turn into extra property names. Each binary gets one label: "stress" if asked for
  # (excluded from the default run), else "unit".
  if("stress" IN_LIST T_LABELS OR "long" IN_LIST T_LABELS)
    set(T_LABEL stress)
  else()
    set(T_LABEL unit)
  endif()
  gtest_discover_tests(${name}
    WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
    DISCOVERY_TIMEOUT 60
    PROPERTIES LABELS ${T_LABEL})
endfunction()
