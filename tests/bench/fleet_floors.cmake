# ctest: a tiny `ocp_bench fleet` run, one loopback and one virtual point, reports the kernel
# floor (the kernel's TCP cost of the loopback point's traffic) with the machine's cores, the
# same traffic paced in the point's shape (its threads, its bursts) and the codec floor (the
# virtual point's codec work alone), all measured after the point; --no-kernel-floor and
# --no-codec-floor leave them out.
# Run as: cmake -DOCP_BENCH=… -DOUT_DIR=… -P fleet_floors.cmake
function(run_fleet json_file)
  file(REMOVE ${json_file})
  execute_process(
    COMMAND ${OCP_BENCH} fleet --loopback 2 --virtual 2 --window-s 0.5 --simulated-s 0.5 --warm-up-s 0.2 --json ${json_file} ${ARGN}
    RESULT_VARIABLE exit_code OUTPUT_VARIABLE output ERROR_VARIABLE errors TIMEOUT 90)
  if(NOT exit_code EQUAL 0)
    message(FATAL_ERROR "ocp_bench fleet ${ARGN} exited with ${exit_code}\n${output}\n${errors}")
  endif()
  file(READ ${json_file} json)
  foreach(index 0 1)
    string(JSON ok GET "${json}" points ${index} ok)
    if(NOT ok)
      message(FATAL_ERROR "point ${index} failed\n${output}")
    endif()
  endforeach()
  set(json "${json}" PARENT_SCOPE)
  set(output "${output}" PARENT_SCOPE)
endfunction()

run_fleet(${OUT_DIR}/ocp_bench_fleet_floor.json)
string(JSON cores GET "${json}" cores)
if(NOT cores GREATER 0)
  message(FATAL_ERROR "cores: ${cores}\n${json}")
endif()
# points[0] is the loopback point, points[1] the virtual one.
foreach(point_field "0;kernel_floor_cpu_per_s" "0;kernel_floor_us_per_vehicle_tick" "0;control_bytes" "0;response_bytes"
                    "0;paced_floor_cpu_per_s" "0;paced_floor_us_per_vehicle_tick" "1;codec_floor_cpu_per_simulated_s" "1;codec_floor_us_per_vehicle_cycle")
  string(JSON value GET "${json}" points ${point_field})
  if(NOT value GREATER 0)
    message(FATAL_ERROR "points ${point_field} is ${value}, expected > 0\n${json}")
  endif()
endforeach()
# The default shape: 2 Streamer threads, one client thread each, 1 slot (one vehicle a thread).
foreach(line "loopback N=2: kernel TCP alone"
             "loopback N=2: kernel TCP paced as the point \\(2 server threads, 1 burst each per 10 ms, the clients' ends on threads of their own\\)"
             "virtual N=2: codec alone")
  if(NOT output MATCHES "${line}")
    message(FATAL_ERROR "no '${line}' line in the report\n${output}")
  endif()
endforeach()

# Paced: its 100 measured periods (1 s) cannot take less than 10 ms each; batched they would
# take a few ms in all.
string(JSON paced_wall GET "${json}" points 0 paced_floor_wall_s)
if(paced_wall LESS 0.98)
  message(FATAL_ERROR "the paced floor's 1 s of periods took ${paced_wall} s: not paced\n${json}")
endif()

# The paced floor follows the point's shape: one thread carrying both ends, two bursts a period.
run_fleet(${OUT_DIR}/ocp_bench_fleet_floor_shape.json --streamer-threads 1 --client-threads 0 --tick-slots 2)
set(line "loopback N=2: kernel TCP paced as the point \\(1 server thread, 2 bursts each per 10 ms, the clients' ends on the server threads\\)")
if(NOT output MATCHES "${line}")
  message(FATAL_ERROR "no '${line}' line in the report\n${output}")
endif()
string(JSON value GET "${json}" points 0 paced_floor_us_per_vehicle_tick)
if(NOT value GREATER 0)
  message(FATAL_ERROR "--client-threads 0: paced_floor_us_per_vehicle_tick is ${value}, expected > 0\n${json}")
endif()

run_fleet(${OUT_DIR}/ocp_bench_fleet_no_floors.json --no-kernel-floor --no-codec-floor)
foreach(point_field "0;kernel_floor_cpu_per_s" "0;kernel_floor_us_per_vehicle_tick" "0;paced_floor_cpu_per_s"
                    "0;paced_floor_us_per_vehicle_tick" "0;paced_floor_wall_s" "1;codec_floor_cpu_per_simulated_s"
                    "1;codec_floor_us_per_vehicle_cycle")
  string(JSON type TYPE "${json}" points ${point_field})
  if(NOT type STREQUAL "NULL")
    message(FATAL_ERROR "--no-kernel-floor --no-codec-floor: points ${point_field} is ${type}, expected null\n${json}")
  endif()
endforeach()
if(output MATCHES "alone")
  message(FATAL_ERROR "--no-kernel-floor --no-codec-floor still reports a floor\n${output}")
endif()
