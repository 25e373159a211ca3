# Finds Python and pybind11 for python/ (RTT_WITH_PYTHON=AUTO|ON). The interpreter defaults to
# Debian's /usr/bin/python3: a pyenv python3 earlier on PATH cannot see Debian's numpy.
if(NOT DEFINED Python_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python_EXECUTABLE /usr/bin/python3)
endif()
set(PYBIND11_FINDPYTHON ON)
find_package(Python 3.9 COMPONENTS Interpreter Development.Module QUIET)
find_package(pybind11 2.6 CONFIG QUIET)
if(NOT (Python_FOUND AND pybind11_FOUND))
  if(RTT_WITH_PYTHON STREQUAL "ON")
    message(FATAL_ERROR "RTT_WITH_PYTHON=ON needs Python 3 development files and pybind11 "
                        "(Debian: python3-dev pybind11-dev python3-numpy)")
  endif()
  message(STATUS "rtt: no pybind11 or Python development files, no Python module")
  return()
endif()

# Where the package goes, relative to the install prefix: the interpreter's site folder for
# the default prefix (/usr/local/lib/python3.X/dist-packages on Debian).
if(NOT DEFINED RTT_PYTHON_INSTALL_DIR)
  execute_process(COMMAND ${Python_EXECUTABLE} -c
    "import sys, sysconfig; v = sys.version_info; site = 'dist-packages' if 'dist-packages' in sysconfig.get_path('platlib') else 'site-packages'; print(f'lib/python{v.major}.{v.minor}/{site}')"
    OUTPUT_VARIABLE _rtt_site OUTPUT_STRIP_TRAILING_WHITESPACE)
  set(RTT_PYTHON_INSTALL_DIR ${_rtt_site} CACHE STRING "Python package folder, relative to the install prefix")
endif()
message(STATUS "rtt: Python module for ${Python_EXECUTABLE}, installed into <prefix>/${RTT_PYTHON_INSTALL_DIR}")
add_subdirectory(python)
