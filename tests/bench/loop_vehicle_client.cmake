# ctest: `ocp_bench loop --compare` against the reference vehicle_client for 2 s, then checks the
# JSON: the client's figures, and each of the three references measured beside it.
# Run as: cmake -DOCP_BENCH=… -DVEHICLE_CLIENT=… -DOUT_DIR=… -P loop_vehicle_client.cmake
set(json_file ${OUT_DIR}/ocp_bench_loop_test.json)
file(REMOVE ${json_file})
execute_process(
  COMMAND ${OCP_BENCH} loop --duration-s 2 --quiet --compare --json ${json_file}
          --max-echo-p50-us 1000000 --fail-on-fault --min-response-rate 20 --max-response-gap-ms 1500
          --max-latency-p99-ms 1000 -- ${VEHICLE_CLIENT} 127.0.0.1:{port}
  RESULT_VARIABLE exit_code OUTPUT_VARIABLE output ERROR_VARIABLE errors TIMEOUT 60)
if(NOT exit_code EQUAL 0)
  message(FATAL_ERROR "ocp_bench loop exited with ${exit_code}\n${output}\n${errors}")
endif()
file(READ ${json_file} json)

# Every figure the report promises is present.
foreach(path "client;echo_delay_us;p50" "client;echo_delay_us;p99" "client;echo_delay_us;p99_9"
             "client;echo_delay_us;max" "client;responses_per_s" "client;max_response_gap_ms"
             "client;latency_ms;p50" "client;tick_lateness_us;p99" "client;faults" "duration_s"
             "floor_echo_us;p50" "ratios;echo_p50_vs_floor" "ratios;echo_p50_vs_bare_client"
             "ratios;echo_p50_vs_timer_client")
  string(JSON value ERROR_VARIABLE missing GET "${json}" ${path})
  if(missing)
    message(FATAL_ERROR "JSON lacks ${path}: ${missing}\n${json}")
  endif()
endforeach()

string(JSON responses GET "${json}" client responses)
if(responses LESS_EQUAL 0)
  message(FATAL_ERROR "no responses\n${json}")
endif()
string(JSON echoes GET "${json}" client echo_delay_us count)
if(echoes LESS_EQUAL 0)
  message(FATAL_ERROR "no echo delays\n${json}")
endif()
# The references answered too: each has echo delays of its own.
foreach(reference bare_client timer_client)
  string(JSON count GET "${json}" ${reference} echo_delay_us count)
  if(count LESS_EQUAL 0)
    message(FATAL_ERROR "the ${reference} reference measured no echo\n${json}")
  endif()
endforeach()
string(JSON floor_count GET "${json}" floor_echo_us count)
if(floor_count LESS_EQUAL 0)
  message(FATAL_ERROR "the machine floor measured no round trip\n${json}")
endif()
# The gates it was held to (budgets any working client meets) passed.
foreach(index 0 1)
  string(JSON passed GET "${json}" gates ${index} passed)
  if(NOT passed STREQUAL "ON")
    message(FATAL_ERROR "gate ${index} failed\n${json}")
  endif()
endforeach()
string(JSON faults GET "${json}" faults_after_connect)
if(NOT faults EQUAL 0)
  message(FATAL_ERROR "faults raised while the client was connected\n${json}")
endif()
string(JSON child_exit_type TYPE "${json}" child_exit)
if(NOT child_exit_type STREQUAL "NULL")
  string(JSON child_exit GET "${json}" child_exit)
  message(FATAL_ERROR "the client exited early (${child_exit})\n${output}")
endif()
