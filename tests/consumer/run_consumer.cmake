# Installs the already-built vehs into <build>/<WORK_NAME>/prefix, checks what the installed
# package exports, then configures and builds a project that uses it (find_package(vehs)) as a
# user would, and runs its programs.
#   -DVEHS_BINARY_DIR=<vehs build>  -DCONSUMER_SOURCE_DIR=<project>  -DGENERATOR=<generator>
#   -DWORK_NAME=<folder under the build, default _consumer>
#   -DRUN="<program> [args]|<program> [args]|..."  (paths relative to the project's build folder,
#      run there in order; each must exit 0; default: consumer)
if(NOT WORK_NAME)
  set(WORK_NAME _consumer)
endif()
if(NOT RUN)
  set(RUN consumer)
endif()
set(work "${VEHS_BINARY_DIR}/${WORK_NAME}")
file(REMOVE_RECURSE "${work}")
execute_process(COMMAND ${CMAKE_COMMAND} --install "${VEHS_BINARY_DIR}" --prefix "${work}/prefix"
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(rc)
  message(FATAL_ERROR "cmake --install failed: ${rc}")
endif()
# the installed targets carry no private dependency and no machine flag into a user's build
file(GLOB_RECURSE exported "${work}/prefix/*/vehsTargets*.cmake")
if(NOT exported)
  message(FATAL_ERROR "no vehsTargets*.cmake under ${work}/prefix")
endif()
foreach(f IN LISTS exported)
  file(READ "${f}" text)
  foreach(private CLI11 FastFloat fast_float -march -mavx -fopenmp)
    string(FIND "${text}" "${private}" at)
    if(NOT at EQUAL -1)
      message(FATAL_ERROR "the installed package exports '${private}' (${f})")
    endif()
  endforeach()
endforeach()
# ... nor do its installed headers include them
file(GLOB_RECURSE headers "${work}/prefix/include/vehs/*.hpp")
foreach(h IN LISTS headers)
  file(STRINGS "${h}" includes REGEX "^#include")
  foreach(private CLI/ fast_float umfpack omp.h)
    string(FIND "${includes}" "${private}" at)
    if(NOT at EQUAL -1)
      message(FATAL_ERROR "${h} includes a private dependency ('${private}')")
    endif()
  endforeach()
endforeach()
# a user's machine need not have the tools' dependencies: the package must configure without them
execute_process(COMMAND ${CMAKE_COMMAND} -S "${CONSUMER_SOURCE_DIR}" -B "${work}/build" -G "${GENERATOR}"
                -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${work}/prefix
                -DCMAKE_DISABLE_FIND_PACKAGE_CLI11=ON -DCMAKE_DISABLE_FIND_PACKAGE_FastFloat=ON
                -DCMAKE_EXPORT_COMPILE_COMMANDS=ON RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "configuring ${CONSUMER_SOURCE_DIR} failed: ${rc}")
endif()
# the library's private dependencies stay out of a user's compile line
file(READ "${work}/build/compile_commands.json" commands)
foreach(private -fopenmp CLI11 fast_float FastFloat umfpack.h -march)
  string(FIND "${commands}" "${private}" at)
  if(NOT at EQUAL -1)
    message(FATAL_ERROR "the consumer's compile line contains '${private}': ${commands}")
  endif()
endforeach()
execute_process(COMMAND ${CMAKE_COMMAND} --build "${work}/build" RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "building ${CONSUMER_SOURCE_DIR} failed: ${rc}")
endif()
string(REPLACE "|" ";" programs "${RUN}")
foreach(program IN LISTS programs)
  separate_arguments(command UNIX_COMMAND "${program}")
  list(GET command 0 exe)
  list(REMOVE_AT command 0)
  execute_process(COMMAND "${work}/build/${exe}" ${command} WORKING_DIRECTORY "${work}/build"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message(STATUS "${program}:\n${out}${err}")
  if(rc)
    message(FATAL_ERROR "${program} exited with ${rc}")
  endif()
endforeach()
