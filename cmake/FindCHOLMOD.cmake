# FindCHOLMOD
# -----------
# Finds SuiteSparse's CHOLMOD (Debian's libsuitesparse-dev ships no CMake config).
#
# Imported target:  CHOLMOD::CHOLMOD   (cholmod + the SuiteSparse libraries it needs)
# Result variables: CHOLMOD_FOUND, CHOLMOD_INCLUDE_DIR, CHOLMOD_LIBRARIES, CHOLMOD_VERSION
# Hints:            CHOLMOD_ROOT (a prefix with include/ and lib/)

find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY cholmod)
find_library(CHOLMOD_SUITESPARSECONFIG_LIBRARY suitesparseconfig)
foreach(component amd camd colamd ccolamd)
  string(TOUPPER ${component} upper)
  find_library(CHOLMOD_${upper}_LIBRARY ${component})
  list(APPEND _cholmod_dependency_vars CHOLMOD_${upper}_LIBRARY)
endforeach()

if(CHOLMOD_INCLUDE_DIR AND EXISTS "${CHOLMOD_INCLUDE_DIR}/cholmod_core.h")
  file(STRINGS "${CHOLMOD_INCLUDE_DIR}/cholmod_core.h" _cholmod_version_lines
       REGEX "#define CHOLMOD_(MAIN|SUB|SUBSUB)_VERSION[ \t]+[0-9]+")
  foreach(part MAIN SUB SUBSUB)
    string(REGEX REPLACE ".*CHOLMOD_${part}_VERSION[ \t]+([0-9]+).*" "\\1" _v_${part} "${_cholmod_version_lines}")
  endforeach()
  set(CHOLMOD_VERSION "${_v_MAIN}.${_v_SUB}.${_v_SUBSUB}")
endif()

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(CHOLMOD
  REQUIRED_VARS CHOLMOD_LIBRARY CHOLMOD_INCLUDE_DIR CHOLMOD_SUITESPARSECONFIG_LIBRARY ${_cholmod_dependency_vars}
  VERSION_VAR CHOLMOD_VERSION)

if(CHOLMOD_FOUND)
  set(CHOLMOD_LIBRARIES ${CHOLMOD_LIBRARY} ${CHOLMOD_AMD_LIBRARY} ${CHOLMOD_CAMD_LIBRARY}
      ${CHOLMOD_COLAMD_LIBRARY} ${CHOLMOD_CCOLAMD_LIBRARY} ${CHOLMOD_SUITESPARSECONFIG_LIBRARY})
  if(NOT TARGET CHOLMOD::CHOLMOD)
    add_library(CHOLMOD::CHOLMOD UNKNOWN IMPORTED)
    set_target_properties(CHOLMOD::CHOLMOD PROPERTIES
      IMPORTED_LOCATION "${CHOLMOD_LIBRARY}"
      INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}"
      INTERFACE_LINK_LIBRARIES "${CHOLMOD_AMD_LIBRARY};${CHOLMOD_CAMD_LIBRARY};${CHOLMOD_COLAMD_LIBRARY};${CHOLMOD_CCOLAMD_LIBRARY};${CHOLMOD_SUITESPARSECONFIG_LIBRARY}")
  endif()
endif()
mark_as_advanced(CHOLMOD_INCLUDE_DIR CHOLMOD_LIBRARY CHOLMOD_SUITESPARSECONFIG_LIBRARY ${_cholmod_dependency_vars})
