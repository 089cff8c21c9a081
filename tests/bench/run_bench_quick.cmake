# SPDX-License-Identifier: MIT
# @brief Runs `telesphere-bench TOPIC --quick --json` and checks that it printed a JSON object,
#        and the invariants the topic reports where CHECKS names them ("a.b<0.01;c>2": a JSON
#        path, < or >, a bound; true and false count as 1 and 0). Invariants are accuracy bounds
#        and counts, never timings (STYLE.md §22: speed figures are printed, not asserted).
execute_process(COMMAND ${BENCH} ${TOPIC} --quick --json
  OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
message("${err}")
message("${out}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "telesphere-bench ${TOPIC} --quick --json exited with ${rc}")
endif()
string(JSON type ERROR_VARIABLE json_error TYPE "${out}")
if(json_error OR NOT type STREQUAL "OBJECT")
  message(FATAL_ERROR "telesphere-bench ${TOPIC} --json did not print a JSON object: ${json_error}")
endif()
foreach(check ${CHECKS})
  if(NOT check MATCHES "^([^<>]+)([<>])(.+)$")
    message(FATAL_ERROR "malformed check '${check}' (want path<bound or path>bound)")
  endif()
  set(path "${CMAKE_MATCH_1}")
  set(op "${CMAKE_MATCH_2}")
  set(bound "${CMAKE_MATCH_3}")
  string(REPLACE "." ";" keys "${path}")
  string(JSON value ERROR_VARIABLE get_error GET "${out}" ${keys})
  if(get_error)
    message(FATAL_ERROR "telesphere-bench ${TOPIC}: no figure ${path} (${get_error})")
  endif()
  if(value STREQUAL "ON")  # a JSON true (string(JSON) writes booleans as ON/OFF): 1
    set(value 1)
  elseif(value STREQUAL "OFF")
    set(value 0)
  endif()
  if((op STREQUAL "<" AND NOT value LESS bound) OR (op STREQUAL ">" AND NOT value GREATER bound))
    message(FATAL_ERROR "telesphere-bench ${TOPIC}: ${path} = ${value}, the invariant is ${op} ${bound}")
  endif()
  message("invariant held: ${path} = ${value} ${op} ${bound}")
endforeach()
