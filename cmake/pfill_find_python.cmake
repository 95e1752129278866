# pfill_choose_python(OUT): the Python interpreter for the pfill module.
# Python3_EXECUTABLE when set; else the first python3 on PATH, then
# /usr/bin/python3, that imports numpy. FindPython alone takes the first
# python3 on PATH, which may be a pyenv shim or a virtualenv without numpy
# (and without the system's python3-dev headers).
function(pfill_choose_python out)
  if(Python3_EXECUTABLE)
    set(${out} ${Python3_EXECUTABLE} PARENT_SCOPE)
    return()
  endif()
  if(WIN32)
    set(dirs $ENV{PATH})
  else()
    string(REPLACE ":" ";" dirs "$ENV{PATH}")
  endif()
  list(APPEND dirs /usr/bin /usr/local/bin)
  foreach(dir ${dirs})
    set(candidate ${dir}/python3)
    if(NOT EXISTS ${candidate} OR IS_DIRECTORY ${candidate})
      continue()
    endif()
    # Prints the folder of Python.h when numpy imports; fails otherwise.
    execute_process(COMMAND ${candidate} -c "import numpy, sysconfig; print(sysconfig.get_paths()['include'])"
                    RESULT_VARIABLE failed OUTPUT_VARIABLE include OUTPUT_STRIP_TRAILING_WHITESPACE
                    ERROR_QUIET TIMEOUT 30)
    if(NOT failed AND EXISTS "${include}/Python.h")
      set(${out} ${candidate} PARENT_SCOPE)
      return()
    endif()
  endforeach()
  set(${out} "" PARENT_SCOPE)
endfunction()
