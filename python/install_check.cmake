# Installs the build tree into a fresh prefix and imports the installed
# module from <prefix>/<PYTHON_DIR> with PYTHON, as a user's interpreter
# would (ctest python_install; run from ${WORK}, not the build directory
# that holds the built module).
file(REMOVE_RECURSE "${WORK}")
execute_process(COMMAND ${CMAKE_COMMAND} --install "${BUILD}" --prefix "${WORK}/prefix"
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${rc})")
endif()
set(dir "${WORK}/prefix/${PYTHON_DIR}")
file(GLOB modules "${dir}/nrsfm*.so")
if(NOT modules)
  message(FATAL_ERROR "no nrsfm module installed in ${dir}")
endif()
execute_process(
  COMMAND ${CMAKE_COMMAND} -E env PYTHONPATH=${dir} PYTHONDONTWRITEBYTECODE=1
          ${PYTHON} -c "import sys, nrsfm; assert nrsfm.__file__.startswith(sys.argv[1]), nrsfm.__file__; s = nrsfm.synth(frames=20, points=10, K=1); print(nrsfm.reconstruct(s.W, 1))" ${dir}
  WORKING_DIRECTORY ${WORK}
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "importing the installed module failed:\n${out}${err}")
endif()
message(STATUS "installed module: ${modules}\n${out}")
file(REMOVE_RECURSE "${WORK}")
