# The two functions every module folder uses (included by the top-level CMakeLists.txt).

# graftnav_add_module(<name> [DEPS module...] [PUBLIC_LIBS lib...] [PRIVATE_LIBS lib...])
# Library graftnav_<name> from <dir>/<name>/src/**/*.cpp (src/ may group its files in subfolders;
# ROOT overrides <dir>/<name>) with public headers in <dir>/<name>/include; header-only when src/
# is empty. DEPS are other graftnav modules (linked PUBLIC, since headers
# include each other). Tests in <dir>/<name>/tests/*.cpp become the executable test_<name>.
function(graftnav_add_module name)
  cmake_parse_arguments(M "" "ROOT" "DEPS;PUBLIC_LIBS;PRIVATE_LIBS;TEST_LIBS" ${ARGN})
  set(dir ${CMAKE_CURRENT_SOURCE_DIR}/${name})
  if(M_ROOT)
    set(dir ${M_ROOT})
  endif()
  set(target graftnav_${name})
  list(TRANSFORM M_DEPS PREPEND graftnav_)
  file(GLOB_RECURSE srcs CONFIGURE_DEPENDS ${dir}/src/*.cpp)
  if(srcs)
    add_library(${target} ${srcs})
    target_include_directories(${target} PUBLIC
      $<BUILD_INTERFACE:${dir}/include> $<INSTALL_INTERFACE:include>)
    target_link_libraries(${target} PUBLIC ${M_DEPS} ${M_PUBLIC_LIBS}
      PRIVATE ${M_PRIVATE_LIBS} graftnav_warnings)
  else()
    add_library(${target} INTERFACE)
    target_include_directories(${target} INTERFACE
      $<BUILD_INTERFACE:${dir}/include> $<INSTALL_INTERFACE:include>)
    target_link_libraries(${target} INTERFACE ${M_DEPS} ${M_PUBLIC_LIBS})
  endif()
  add_library(graftnav::${name} ALIAS ${target})
  if(GRAFTNAV_BUILD_PYTHON AND srcs)
    # Linked into the Python module, a shared object (the executables stay as they were).
    set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  endif()
  # Installed as graftnav::<name> (find_package(graftnav)), headers merged under include/graftnav.
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})
  install(TARGETS ${target} EXPORT graftnavTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY ${dir}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  if(GRAFTNAV_BUILD_TESTS)
    graftnav_add_tests(test_${name} ${dir}/tests LIBS ${target} graftnav_core ${M_TEST_LIBS})
  endif()
endfunction()

# graftnav_add_tests(<exe> <folder> LIBS lib...): one GoogleTest executable from <folder>/*.cpp with
# the shared helpers of tests/support. Tests find the shared data folder through
# GRAFTNAV_SHARED_DIR, the repo through GRAFTNAV_SOURCE_DIR and the CLI through GRAFTNAV_BINARY.
function(graftnav_add_tests exe folder)
  cmake_parse_arguments(T "" "" "LIBS" ${ARGN})
  file(GLOB srcs CONFIGURE_DEPENDS ${folder}/*.cpp)
  if(NOT srcs)
    return()
  endif()
  add_executable(${exe} ${srcs})
  target_link_libraries(${exe} PRIVATE ${T_LIBS} graftnav_test_support GTest::gtest
    GTest::gtest_main GTest::gmock nlohmann_json::nlohmann_json yaml-cpp fmt::fmt graftnav_warnings)
  target_compile_definitions(${exe} PRIVATE
    GRAFTNAV_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    GRAFTNAV_SHARED_DIR="${PROJECT_SOURCE_DIR}/../shared"
    GRAFTNAV_BINARY="$<TARGET_FILE:graftnav>")
  # End-to-end tests run the built `graftnav` binary.
  add_dependencies(${exe} graftnav)
  gtest_discover_tests(${exe} DISCOVERY_TIMEOUT 60 PROPERTIES TIMEOUT 600)
endfunction()
