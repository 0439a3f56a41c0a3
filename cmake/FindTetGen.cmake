# FindTetGen
# ----------
# Finds TetGen built as a library (Debian/Ubuntu: libtet1.5-dev, header tetgen.h, library tet).
#
# Result variables: TetGen_FOUND, TetGen_INCLUDE_DIR, TetGen_LIBRARY.
# Imported target: TetGen::TetGen, which carries the compile definition TETLIBRARY that
# tetgen.h needs to declare the library interface (tetrahedralize(char*, ...), errors thrown as
# int instead of exit()). Hints: TetGen_ROOT or CMAKE_PREFIX_PATH.

find_path(TetGen_INCLUDE_DIR tetgen.h PATH_SUFFIXES tetgen)
find_library(TetGen_LIBRARY NAMES tet tetgen)

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(TetGen REQUIRED_VARS TetGen_LIBRARY TetGen_INCLUDE_DIR)

if(TetGen_FOUND AND NOT TARGET TetGen::TetGen)
  # GLOBAL: barylab_core is a static library, so its consumers in other directories link
  # TetGen::TetGen too.
  add_library(TetGen::TetGen UNKNOWN IMPORTED GLOBAL)
  set_target_properties(TetGen::TetGen PROPERTIES
    IMPORTED_LOCATION "${TetGen_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${TetGen_INCLUDE_DIR}"
    INTERFACE_COMPILE_DEFINITIONS TETLIBRARY)
endif()
mark_as_advanced(TetGen_INCLUDE_DIR TetGen_LIBRARY)
