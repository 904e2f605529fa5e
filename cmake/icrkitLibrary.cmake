# icrkit_add_library(<name> SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
#
# Declares the library target icrkit_<name> with the alias icrkit::<name>,
# headers under libs/<name>/include/icrkit/<name>/, installed and exported.
function(icrkit_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(target icrkit_${name})
  if(NOT ARG_SOURCES)
    message(FATAL_ERROR "icrkit_add_library(${name}): SOURCES is required")
  endif()
  add_library(${target} ${ARG_SOURCES})
  target_link_libraries(${target} PRIVATE ${ARG_PRIVATE_DEPS})
  add_library(icrkit::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME icrkit_${name})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_compile_features(${target} PUBLIC cxx_std_17)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_DEPS})
  if(ICRKIT_SANITIZE)
    # A sanitized static library needs the sanitizer runtimes wherever it is
    # linked, including in projects that consume the installed package.
    target_link_options(${target} INTERFACE -fsanitize=address,undefined)
  endif()
  install(TARGETS ${target} EXPORT icrkitTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()

# icrkit_add_test(<name> SOURCES ... DEPS ...): one GoogleTest binary, registered with ctest.
function(icrkit_add_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gtest_main)
  # The one shared test-support header (tests/support/test_support.hpp).
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR}/tests/support)
  target_compile_definitions(${name} PRIVATE
    ICRKIT_SHARED_DATA_DIR="${ICRKIT_SHARED_DATA_DIR}"
    ICRKIT_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  # A hang (e.g. a reader looping on corrupted input) fails instead of stalling CI.
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES TIMEOUT ${ICRKIT_TEST_TIMEOUT})
endfunction()
