# Script mode, for ctest. package.consumer (PFILL_BUILD given): installs the
# pfill build PFILL_BUILD into WORK/prefix, configures CONSUMER_SOURCE against
# it with only -DCMAKE_PREFIX_PATH, builds it and runs it.
# package.add_subdirectory (PFILL_SOURCE given): configures CONSUMER_SOURCE
# with pfill's sources added by add_subdirectory. Any failing step fails.
function(step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "run_consumer: ${what} failed (${rc})")
  endif()
endfunction()

file(REMOVE_RECURSE ${WORK})
if(PFILL_SOURCE)
  step("configuring the consumer with add_subdirectory" ${CMAKE_COMMAND} -S ${CONSUMER_SOURCE} -B ${WORK}
       -G ${GENERATOR} -DPFILL_SOURCE_DIR=${PFILL_SOURCE})
  return()
endif()
set(prefix ${WORK}/prefix)
if(NOT CONFIG)
  set(CONFIG Release)
endif()
step("cmake --install" ${CMAKE_COMMAND} --install ${PFILL_BUILD} --prefix ${prefix} --config ${CONFIG})
step("configuring the consumer" ${CMAKE_COMMAND} -S ${CONSUMER_SOURCE} -B ${WORK}/build -G ${GENERATOR}
     -DCMAKE_PREFIX_PATH=${prefix})
step("building the consumer" ${CMAKE_COMMAND} --build ${WORK}/build)
execute_process(COMMAND ${WORK}/build/pfill_consumer sphere 300 RESULT_VARIABLE rc OUTPUT_VARIABLE out)
message("${out}")
if(NOT rc EQUAL 0 OR NOT out MATCHES "with [1-9][0-9]* particles of radius")
  message(FATAL_ERROR "package.consumer: the consumer did not fill the sphere (${rc})")
endif()
