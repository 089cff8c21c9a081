# SPDX-License-Identifier: MIT
# @brief Runs `telesphere-bench TOPIC --quick --json` and checks that it printed a JSON object
#        (the figures themselves are printed, never asserted: STYLE.md §22).
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
