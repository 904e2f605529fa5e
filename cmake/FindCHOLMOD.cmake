# FindCHOLMOD: SuiteSparse's CHOLMOD, which Debian ships without a CMake config.
#
# Defines the imported target CHOLMOD::CHOLMOD and CHOLMOD_FOUND,
# CHOLMOD_INCLUDE_DIR, CHOLMOD_LIBRARY, CHOLMOD_VERSION.
find_path(CHOLMOD_INCLUDE_DIR NAMES cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY NAMES cholmod)
find_library(CHOLMOD_SUITESPARSECONFIG_LIBRARY NAMES suitesparseconfig)

# The version macros sit in cholmod_core.h in SuiteSparse 5, in cholmod.h later.
foreach(_hdr cholmod_core.h cholmod.h)
  if(NOT CHOLMOD_VERSION AND CHOLMOD_INCLUDE_DIR AND EXISTS "${CHOLMOD_INCLUDE_DIR}/${_hdr}")
  file(STRINGS "${CHOLMOD_INCLUDE_DIR}/${_hdr}" _cholmod_version_lines
       REGEX "#define CHOLMOD_(MAIN|SUB)_VERSION")
  string(REGEX REPLACE ".*MAIN_VERSION[ \t]+([0-9]+).*" "\\1" _major "${_cholmod_version_lines}")
  string(REGEX REPLACE ".*SUB_VERSION[ \t]+([0-9]+).*" "\\1" _minor "${_cholmod_version_lines}")
  if(_cholmod_version_lines)
    set(CHOLMOD_VERSION "${_major}.${_minor}")
  endif()
  endif()
endforeach()

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(CHOLMOD
  REQUIRED_VARS CHOLMOD_LIBRARY CHOLMOD_INCLUDE_DIR
  VERSION_VAR CHOLMOD_VERSION)

if(CHOLMOD_FOUND AND NOT TARGET CHOLMOD::CHOLMOD)
  add_library(CHOLMOD::CHOLMOD UNKNOWN IMPORTED)
  set_target_properties(CHOLMOD::CHOLMOD PROPERTIES
    IMPORTED_LOCATION "${CHOLMOD_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}")
  if(CHOLMOD_SUITESPARSECONFIG_LIBRARY)
    set_property(TARGET CHOLMOD::CHOLMOD APPEND PROPERTY
      INTERFACE_LINK_LIBRARIES "${CHOLMOD_SUITESPARSECONFIG_LIBRARY}")
  endif()
endif()
mark_as_advanced(CHOLMOD_INCLUDE_DIR CHOLMOD_LIBRARY CHOLMOD_SUITESPARSECONFIG_LIBRARY)
