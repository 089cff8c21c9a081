# SPDX-License-Identifier: MIT
# @brief The travelling render benchmark needs no library that a GPU machine lacks: its
#        NEEDED entries (readelf -d) are only GL/EGL (glvnd), libpng/zlib, TurboJPEG (all three
#        linked statically in the travelling build), the C/C++ runtime and, in sanitizer builds,
#        their runtimes. Anything else (protobuf, Ceres, OpenCV, Qt, spdlog, yaml-cpp, ZeroMQ)
#        fails the test, naming it.
execute_process(COMMAND readelf -d ${BINARY} OUTPUT_VARIABLE out RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "readelf -d ${BINARY} failed (${rc})")
endif()
string(REGEX MATCHALL "Shared library: \\[[^]]+\\]" needed "${out}")
if(NOT needed)
  message(FATAL_ERROR "readelf -d ${BINARY} listed no shared libraries:\n${out}")
endif()
set(allowed "^(lib(OpenGL|EGL|GL|GLX|GLdispatch|png16|z|turbojpeg|stdc\\+\\+|m|gcc_s|c|pthread|dl|rt|asan|ubsan)\\.so|ld-linux)")
set(unexpected "")
foreach(entry ${needed})
  string(REGEX REPLACE "Shared library: \\[([^]]+)\\]" "\\1" lib "${entry}")
  message("needs ${lib}")
  if(NOT lib MATCHES "${allowed}")
    list(APPEND unexpected ${lib})
  endif()
endforeach()
if(unexpected)
  message(FATAL_ERROR "telesphere-render-bench needs libraries a GPU machine may lack: ${unexpected}")
endif()
