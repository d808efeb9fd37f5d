# cmake -DDOC=docs/insitu.md -DWORK=<dir> -DINCLUDE=<canopy include dir> -DLIBRARY=<libcanopy.so>
#       -DMPICC=<mpicc> [-DMPIFORT=<mpif90>] -P doc_snippets.cmake
# Compiles and links the programs of docs/insitu.md's "C and Fortran" section (the
# first ```c and ```fortran blocks) against canopy.h / canopy.f90 and the library,
# so that the documentation keeps matching the real signatures.
file(READ "${DOC}" _doc)
string(FIND "${_doc}" "\n## C and Fortran\n" _start)
if(_start EQUAL -1)
  message(FATAL_ERROR "${DOC}: no '## C and Fortran' section")
endif()
math(EXPR _start "${_start} + 1")
string(SUBSTRING "${_doc}" ${_start} -1 _section)
string(FIND "${_section}" "\n## " _end) # the next section
if(NOT _end EQUAL -1)
  string(SUBSTRING "${_section}" 0 ${_end} _section)
endif()

file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
get_filename_component(_libdir "${LIBRARY}" DIRECTORY)

function(_compile language extension)
  string(FIND "${_section}" "```${language}\n" _open)
  if(_open EQUAL -1)
    message(FATAL_ERROR "no ```${language} block in the C and Fortran section")
  endif()
  string(LENGTH "```${language}\n" _fence)
  math(EXPR _open "${_open} + ${_fence}")
  string(SUBSTRING "${_section}" ${_open} -1 _code)
  string(FIND "${_code}" "\n```" _close)
  string(SUBSTRING "${_code}" 0 ${_close} _code)
  file(WRITE "${WORK}/snippet.${extension}" "${_code}\n")
  set(_command ${ARGN} "${WORK}/snippet.${extension}" "${LIBRARY}" "-Wl,-rpath-link,${_libdir}"
    -o "${WORK}/snippet_${extension}")
  message(STATUS "${_command}")
  execute_process(COMMAND ${_command} WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE _result)
  if(NOT _result EQUAL 0)
    message(FATAL_ERROR "the ```${language} program of ${DOC} does not build")
  endif()
  message(STATUS "ok: the ```${language} program builds")
endfunction()

_compile(c c ${MPICC} -std=c99 -pedantic -Wall -Wextra -Werror "-I${INCLUDE}")
if(MPIFORT)
  _compile(fortran f90 ${MPIFORT} -Wall -Werror "-J${WORK}" "${INCLUDE}/canopy/canopy.f90")
endif()
