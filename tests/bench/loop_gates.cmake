# ctest: the gates of `ocp_bench loop` can fail. A gate that fails prints ✗ with expected and
# actual, sets "passed": false in the JSON and makes the exit code 1; the gates that hold stay ✓.
# (The passing side: loop_vehicle_client.cmake holds the reference client to gates it meets.)
# Run as: cmake -DOCP_BENCH=… -DVEHICLE_CLIENT=… -DOUT_DIR=… -P loop_gates.cmake
function(run_gated name expected_gates)
  set(json_file ${OUT_DIR}/ocp_bench_loop_gates_${name}.json)
  file(REMOVE ${json_file})
  execute_process(COMMAND ${OCP_BENCH} loop --quiet --json ${json_file} ${ARGN}
                  RESULT_VARIABLE exit_code OUTPUT_VARIABLE output ERROR_VARIABLE errors TIMEOUT 60)
  if(NOT exit_code EQUAL 1)
    message(FATAL_ERROR "${name}: exit ${exit_code}, expected 1 (a gate failed)\n${output}\n${errors}")
  endif()
  file(READ ${json_file} json)
  string(JSON count LENGTH "${json}" gates)
  list(LENGTH expected_gates expected_count)
  if(NOT count EQUAL expected_count)
    message(FATAL_ERROR "${name}: ${count} gates in the JSON, expected ${expected_count}\n${json}")
  endif()
  set(index 0)
  foreach(expected ${expected_gates})
    string(JSON passed GET "${json}" gates ${index} passed)
    if(NOT passed STREQUAL expected)
      message(FATAL_ERROR "${name}: gate ${index} passed=${passed}, expected ${expected}\n${json}")
    endif()
    math(EXPR index "${index} + 1")
  endforeach()
  string(FIND "${output}" "✗" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${name}: no ✗ line in the table\n${output}")
  endif()
endfunction()

# An echo budget met, and a p99 budget and a floor ratio no client meets, in one run.
run_gated(ratio "ON;OFF;OFF" --duration-s 1 --compare --max-echo-p50-us 1000000 --max-echo-p99-us 0.001
          --max-floor-ratio 0.001 -- ${VEHICLE_CLIENT} 127.0.0.1:{port})
# A client that keeps echoing its first pair: HighLatency once latency passes the limit (500 ms);
# and a p50 budget no client meets.
run_gated(fault "OFF;OFF" --duration-s 2 --max-echo-p50-us 0.001 --fail-on-fault
          -- ${VEHICLE_CLIENT} 127.0.0.1:{port} --misbehave-stop-echo)
# The loop gates: a rate, a gap and a latency budget no client meets (the reference client
# answers about 100 times a second, at most ~10 ms apart, with a loop latency of milliseconds).
run_gated(loop "OFF;OFF;OFF" --duration-s 1 --min-response-rate 100000 --max-response-gap-ms 0.001
          --max-latency-p99-ms 0.001 -- ${VEHICLE_CLIENT} 127.0.0.1:{port})
