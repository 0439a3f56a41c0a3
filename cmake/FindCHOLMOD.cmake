# FindCHOLMOD
# -----------
# Finds SuiteSparse's CHOLMOD (sparse Cholesky). Debian/Ubuntu ship no CMake config or
# pkg-config file for it, so this module looks for the header and the libraries directly.
#
# Result variables:
#   CHOLMOD_FOUND         - TRUE when cholmod.h and every library below were found
#   CHOLMOD_INCLUDE_DIRS  - directory holding cholmod.h (e.g. /usr/include/suitesparse)
#   CHOLMOD_LIBRARIES     - cholmod, amd, colamd, camd, ccolamd, suitesparseconfig
#   CHOLMOD_VERSION       - from CHOLMOD_MAIN/SUB/SUBSUB_VERSION in cholmod_core.h (or cholmod.h)
# Imported target (GLOBAL, so that targets in other directories which link a static library
# depending on it can resolve it):
#   CHOLMOD::CHOLMOD
# Hints: CHOLMOD_ROOT or SuiteSparse_ROOT (CMake >= 3.12 searches <Pkg>_ROOT), CMAKE_PREFIX_PATH.

find_path(CHOLMOD_INCLUDE_DIR cholmod.h
  HINTS ${SuiteSparse_ROOT} ENV SuiteSparse_ROOT
  PATH_SUFFIXES suitesparse include/suitesparse include)

set(_cholmod_components cholmod amd colamd camd ccolamd suitesparseconfig)
set(_cholmod_library_vars)
foreach(_lib ${_cholmod_components})
  string(TOUPPER "${_lib}" _LIB)
  find_library(CHOLMOD_${_LIB}_LIBRARY NAMES ${_lib}
    HINTS ${SuiteSparse_ROOT} ENV SuiteSparse_ROOT
    PATH_SUFFIXES lib lib64)
  mark_as_advanced(CHOLMOD_${_LIB}_LIBRARY)
  list(APPEND _cholmod_library_vars CHOLMOD_${_LIB}_LIBRARY)
endforeach()

set(CHOLMOD_VERSION "")
if(CHOLMOD_INCLUDE_DIR)
  foreach(_header cholmod_core.h cholmod.h)
    if(EXISTS "${CHOLMOD_INCLUDE_DIR}/${_header}" AND NOT CHOLMOD_VERSION)
      file(STRINGS "${CHOLMOD_INCLUDE_DIR}/${_header}" _cholmod_version_lines
        REGEX "^#define[ \t]+CHOLMOD_(MAIN|SUB|SUBSUB)_VERSION[ \t]+[0-9]+")
      set(_v_main "")
      set(_v_sub "")
      set(_v_subsub "")
      foreach(_line ${_cholmod_version_lines})
        if(_line MATCHES "CHOLMOD_MAIN_VERSION[ \t]+([0-9]+)")
          set(_v_main "${CMAKE_MATCH_1}")
        elseif(_line MATCHES "CHOLMOD_SUB_VERSION[ \t]+([0-9]+)")
          set(_v_sub "${CMAKE_MATCH_1}")
        elseif(_line MATCHES "CHOLMOD_SUBSUB_VERSION[ \t]+([0-9]+)")
          set(_v_subsub "${CMAKE_MATCH_1}")
        endif()
      endforeach()
      if(NOT _v_main STREQUAL "")
        set(CHOLMOD_VERSION "${_v_main}.${_v_sub}.${_v_subsub}")
      endif()
    endif()
  endforeach()
endif()

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(CHOLMOD
  REQUIRED_VARS CHOLMOD_CHOLMOD_LIBRARY CHOLMOD_INCLUDE_DIR ${_cholmod_library_vars}
  VERSION_VAR CHOLMOD_VERSION)
mark_as_advanced(CHOLMOD_INCLUDE_DIR)

if(CHOLMOD_FOUND)
  set(CHOLMOD_INCLUDE_DIRS "${CHOLMOD_INCLUDE_DIR}")
  set(CHOLMOD_LIBRARIES)
  foreach(_var ${_cholmod_library_vars})
    list(APPEND CHOLMOD_LIBRARIES "${${_var}}")
  endforeach()
  if(NOT TARGET CHOLMOD::CHOLMOD)
    add_library(CHOLMOD::CHOLMOD UNKNOWN IMPORTED GLOBAL)
    set(_cholmod_dependencies ${CHOLMOD_LIBRARIES})
    list(REMOVE_ITEM _cholmod_dependencies "${CHOLMOD_CHOLMOD_LIBRARY}")
    set_target_properties(CHOLMOD::CHOLMOD PROPERTIES
      IMPORTED_LOCATION "${CHOLMOD_CHOLMOD_LIBRARY}"
      INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}"
      INTERFACE_LINK_LIBRARIES "${_cholmod_dependencies}")
  endif()
endif()

unset(_cholmod_components)
unset(_cholmod_library_vars)
unset(_cholmod_dependencies)
