# What the tests need to know about an ASan build (scripts/sanitize, docs/sanitizers.md):
# PRINCIPLED_ASAN: ON when CMAKE_CXX_FLAGS has -fsanitize=address.
# PRINCIPLED_SANITIZER_PRELOAD: what a non-instrumented host process must LD_PRELOAD before it
# can load one of our ASan-instrumented shared objects (the Python module inside
# /usr/bin/python3): the ASan runtime, which must come first in the process ("ASan runtime does
# not come first in initial library list" otherwise), and libstdc++, because python3 does not
# link it and ASan must find the real __cxa_throw at start-up, or its interceptor aborts on our
# first C++ throw ("CHECK failed: asan_interceptors.cpp:320 real___cxa_throw != 0").
# Space-separated, as LD_PRELOAD takes it. Empty unless CMAKE_CXX_FLAGS has -fsanitize=address.
# gcc only (libasan.so); docs/sanitizers.md.
set(PRINCIPLED_SANITIZER_PRELOAD "")
set(PRINCIPLED_ASAN OFF)
if(CMAKE_CXX_FLAGS MATCHES "-fsanitize=[^ ]*address")
  set(PRINCIPLED_ASAN ON)
endif()
if(PRINCIPLED_ASAN AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-file-name=libasan.so
                  OUTPUT_VARIABLE _principled_asan_rt OUTPUT_STRIP_TRAILING_WHITESPACE)
  execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-file-name=libstdc++.so
                  OUTPUT_VARIABLE _principled_stdcxx OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(IS_ABSOLUTE "${_principled_asan_rt}" AND EXISTS "${_principled_asan_rt}")
    set(PRINCIPLED_SANITIZER_PRELOAD "${_principled_asan_rt} ${_principled_stdcxx}")
    message(STATUS "principled: ASan build; the Python tests preload ${PRINCIPLED_SANITIZER_PRELOAD}")
  else()
    message(WARNING "principled: ASan build but libasan.so was not found; "
                    "the Python tests will fail to import the module")
  endif()
endif()
