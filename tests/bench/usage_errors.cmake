# ctest: bad command lines make `ocp_bench` exit 2 (usage error), --help exits 0.
# Run as: cmake -DOCP_BENCH=… -P usage_errors.cmake
foreach(arguments "loop;--bogus" "loop;--duration-s;abc" "loop;--duration-s;0" "loop;--duration-s;nan" "loop;--duration-s;inf" "fleet;--window-s;nan" "fleet;--client-threads;-1" "fleet;--client-threads;nan" "fleet;--client-threads;65" "loop;--port;70000" "loop;--max-floor-ratio;2" "loop;--max-echo-p50-us;nan" "loop;--max-echo-p99-us;-1" "loop;--max-echo-p50-us;0" "" "nosuch")
  execute_process(COMMAND ${OCP_BENCH} ${arguments} RESULT_VARIABLE exit_code OUTPUT_QUIET ERROR_QUIET TIMEOUT 20)
  if(NOT exit_code EQUAL 2)
    message(FATAL_ERROR "ocp_bench ${arguments}: exit ${exit_code}, expected 2")
  endif()
endforeach()
execute_process(COMMAND ${OCP_BENCH} loop --help RESULT_VARIABLE exit_code OUTPUT_QUIET TIMEOUT 20)
if(NOT exit_code EQUAL 0)
  message(FATAL_ERROR "ocp_bench loop --help: exit ${exit_code}, expected 0")
endif()
