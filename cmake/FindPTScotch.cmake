# Finds PT-Scotch (Debian: libptscotch-dev) and exports PTScotch::PTScotch.
# Debian installs Scotch once per index width, headers and libraries in
# matching directories (include/scotch-int64, lib/<arch>/scotch-int64, ...).
# The 64-bit build is preferred, so that meshes past 2^31 face adjacencies
# still partition; PTSCOTCH_VARIANT picks another (scotch-int32,
# scotch-long). Headers and libraries always come from the same variant:
# mixing widths would pass 64-bit arrays to a 32-bit library.
set(PTSCOTCH_VARIANT "scotch-int64" CACHE STRING "Debian's Scotch variant (directory name)")
find_path(PTSCOTCH_INCLUDE_DIR ptscotch.h PATH_SUFFIXES ${PTSCOTCH_VARIANT})
set(ptscotch_library_hints)
if(PTSCOTCH_INCLUDE_DIR)
  get_filename_component(ptscotch_include_name "${PTSCOTCH_INCLUDE_DIR}" NAME)
  if(ptscotch_include_name STREQUAL PTSCOTCH_VARIANT)
    get_filename_component(ptscotch_prefix "${PTSCOTCH_INCLUDE_DIR}/../.." ABSOLUTE)
    set(ptscotch_library_hints "${ptscotch_prefix}/lib/${CMAKE_LIBRARY_ARCHITECTURE}/${PTSCOTCH_VARIANT}"
                               "${ptscotch_prefix}/lib/${PTSCOTCH_VARIANT}")
  endif()
endif()
foreach(lib ptscotch scotch ptscotcherr)
  string(TOUPPER ${lib} var)
  if(ptscotch_library_hints)
    find_library(PTSCOTCH_${var}_LIBRARY ${lib} PATHS ${ptscotch_library_hints} NO_DEFAULT_PATH)
  else()
    find_library(PTSCOTCH_${var}_LIBRARY ${lib})
  endif()
  mark_as_advanced(PTSCOTCH_${var}_LIBRARY)
endforeach()
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(
  PTScotch REQUIRED_VARS PTSCOTCH_PTSCOTCH_LIBRARY PTSCOTCH_SCOTCH_LIBRARY
                         PTSCOTCH_PTSCOTCHERR_LIBRARY PTSCOTCH_INCLUDE_DIR)
if(PTScotch_FOUND AND NOT TARGET PTScotch::PTScotch)
  add_library(PTScotch::PTScotch INTERFACE IMPORTED)
  set_target_properties(
    PTScotch::PTScotch
    PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${PTSCOTCH_INCLUDE_DIR}"
               INTERFACE_LINK_LIBRARIES
               "${PTSCOTCH_PTSCOTCH_LIBRARY};${PTSCOTCH_SCOTCH_LIBRARY};${PTSCOTCH_PTSCOTCHERR_LIBRARY};MPI::MPI_C")
endif()
set(PTSCOTCH_FOUND ${PTScotch_FOUND})
mark_as_advanced(PTSCOTCH_INCLUDE_DIR)
