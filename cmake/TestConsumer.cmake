# Installs cdkit from CDKIT_BINARY_DIR into WORK_DIR/prefix and builds examples/consumer against it with
# CONSUMER_GENERATOR, CONSUMER_MAKE_PROGRAM and CONSUMER_CXX_COMPILER (the project's).
file(REMOVE_RECURSE ${WORK_DIR})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${CDKIT_BINARY_DIR} --prefix ${WORK_DIR}/prefix
  RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "cmake --install failed (${rc})")
endif()
# The project's own generator, build tool and compiler: a fresh machine set up by scripts/install-deps has Ninja but
# no make (CMake's default generator), and the sanitizer job's compiler is clang.
execute_process(COMMAND ${CMAKE_COMMAND} -S ${CDKIT_SOURCE_DIR}/examples/consumer -B ${WORK_DIR}/build
  -G ${CONSUMER_GENERATOR} -DCMAKE_MAKE_PROGRAM=${CONSUMER_MAKE_PROGRAM} -DCMAKE_CXX_COMPILER=${CONSUMER_CXX_COMPILER}
  -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=${CMAKE_BUILD_TYPE}
  "-DCMAKE_CXX_FLAGS=${CONSUMER_CXX_FLAGS}" RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "configuring the consumer project failed (${rc})")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/build RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "building the consumer project failed (${rc})")
endif()
execute_process(COMMAND ${WORK_DIR}/build/consumer ${CDKIT_SOURCE_DIR}/data/bunny.obj RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "running the consumer failed (${rc})")
endif()
