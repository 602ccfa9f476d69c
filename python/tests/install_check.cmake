# ctest python_install: `cmake --install` of the build into a scratch prefix, then the installed package is imported
# (from there, not from the build tree) and answers a query.
file(REMOVE_RECURSE ${WORK_DIR})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BINARY_DIR} --prefix ${WORK_DIR}/prefix --component python
  RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "cmake --install failed (${rc})")
endif()
set(_site ${WORK_DIR}/prefix/${SITE})
if(NOT EXISTS ${_site}/cdkit/__init__.py OR NOT EXISTS ${_site}/cdkit/__init__.pyi)
  message(FATAL_ERROR "the package is not under ${_site}/cdkit")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=PYTHONPATH PYTHONPATH=${_site} ${PYTHON} -c
  "import cdkit, numpy as np; assert cdkit.__file__.startswith('${_site}'), cdkit.__file__; \
v = np.array([[0,0,0],[1,0,0],[0,1,0],[0,0,1]], float); f = np.array([[0,1,2],[0,1,3],[0,2,3],[1,2,3]]); \
m = cdkit.MeshModel(v, f); assert cdkit.collide(m, None, m, None).colliding; print('installed cdkit ok:', cdkit.__file__)"
  WORKING_DIRECTORY ${WORK_DIR} RESULT_VARIABLE rc)  # not the build tree's directory, which holds a cdkit/ too
if(rc)
  message(FATAL_ERROR "importing the installed package failed (${rc})")
endif()
