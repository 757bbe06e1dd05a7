# The Python module `penumbra` (python/penumbra_module.cpp, pybind11): built when pybind11 and an
# interpreter with NumPy are found, into ${PROJECT_BINARY_DIR}/python (PYTHONPATH for the build
# tree), installed to ${PENUMBRA_PYTHON_INSTALL_DIR}. Off under the sanitizers: an instrumented
# extension needs the ASan runtime preloaded into the interpreter. Off by default in a user's
# add_subdirectory too.
if(PENUMBRA_SANITIZE OR NOT PROJECT_IS_TOP_LEVEL)
  set(penumbra_python_default OFF)
else()
  set(penumbra_python_default ON)
endif()
option(PENUMBRA_PYTHON "Build the Python module (pybind11, NumPy)" ${penumbra_python_default})
if(NOT PENUMBRA_PYTHON)
  return()
endif()

# Debian's pybind11, NumPy and pytest belong to /usr/bin/python3, which need not be the first
# python3 on PATH (pyenv, conda): that interpreter unless Python_EXECUTABLE says otherwise.
if(NOT DEFINED Python_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "The interpreter the Python module is built for")
endif()
set(PYBIND11_FINDPYTHON ON)
find_package(Python COMPONENTS Interpreter Development.Module QUIET)
find_package(pybind11 CONFIG QUIET)
if(NOT Python_FOUND OR NOT pybind11_FOUND)
  message(STATUS "pybind11 or Python's headers (pybind11-dev, python3-dev) not found: building without the Python module")
  return()
endif()
execute_process(COMMAND ${Python_EXECUTABLE} -c "import numpy" RESULT_VARIABLE numpy_missing
                OUTPUT_QUIET ERROR_QUIET)
if(numpy_missing)
  message(STATUS "${Python_EXECUTABLE} has no NumPy (python3-numpy): building without the Python module")
  return()
endif()

set(PENUMBRA_HAVE_PYTHON ON)
file(GLOB python_sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/python/*.cpp)
pybind11_add_module(penumbra_python ${python_sources})
set_target_properties(penumbra_python PROPERTIES OUTPUT_NAME penumbra
                      LIBRARY_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/python)
target_link_libraries(penumbra_python PRIVATE penumbra penumbra_warnings)

# The interpreter's own site-packages folder name, under the prefix (Debian: lib/python3/dist-packages).
set(PENUMBRA_PYTHON_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/python3/dist-packages CACHE STRING
    "Where cmake --install puts the Python module, relative to the prefix")
install(TARGETS penumbra_python LIBRARY DESTINATION ${PENUMBRA_PYTHON_INSTALL_DIR})
