# Helpers in the spirit of mola_add_library: one call per target, consistent
# flags, include/ PUBLIC and src/ PRIVATE, alias hymm::<name>, installed and exported.

function(hymm_set_warnings target)
    target_compile_options(${target} PRIVATE -Wall -Wextra -Wshadow)
    if(HYMM_NATIVE AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
        # GCC 12 reports Eigen's AVX packet loads on 2x2 products as out of bounds in
        # branches Eigen never takes for that size (the sanitizer build checks the real
        # accesses).
        target_compile_options(${target} PRIVATE -Wno-array-bounds)
    endif()
    if(HYMM_WERROR)
        target_compile_options(${target} PRIVATE -Werror)
    endif()
endfunction()

# hymm_add_library(NAME SOURCES ... PUBLIC_LINK_LIBRARIES ... PRIVATE_LINK_LIBRARIES ...)
function(hymm_add_library name)
    cmake_parse_arguments(A "" "" "SOURCES;PUBLIC_LINK_LIBRARIES;PRIVATE_LINK_LIBRARIES" ${ARGN})
    set(target hymm_${name})
    add_library(${target} ${A_SOURCES})
    add_library(hymm::${name} ALIAS ${target})
    set_target_properties(${target} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME hymm_${name}
                          POSITION_INDEPENDENT_CODE ON)
    target_compile_features(${target} PUBLIC cxx_std_17)
    target_include_directories(${target}
        PUBLIC $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
               $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>
        PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
    target_link_libraries(${target} PUBLIC ${A_PUBLIC_LINK_LIBRARIES}
                                    PRIVATE ${A_PRIVATE_LINK_LIBRARIES})
    hymm_set_warnings(${target})
    if(HYMM_NATIVE)
        # AVX-512 is left out: GCC 12 warns inside its own intrinsics headers with Eigen.
        target_compile_options(${target} PUBLIC -march=native -mno-avx512f)
    endif()
    install(TARGETS ${target} EXPORT hymmTargets
            ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
            LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
            RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
    install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()

# hymm_add_executable(NAME SOURCES ... LINK_LIBRARIES ...)
function(hymm_add_executable name)
    cmake_parse_arguments(A "" "" "SOURCES;LINK_LIBRARIES" ${ARGN})
    add_executable(${name} ${A_SOURCES})
    target_link_libraries(${name} PRIVATE ${A_LINK_LIBRARIES})
    hymm_set_warnings(${name})
    set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/bin)
    install(TARGETS ${name} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endfunction()

# hymm_add_test(NAME SOURCES ... LINK_LIBRARIES ... [LABELS ...] [COST n])
# GoogleTest executable registered with ctest; test data paths come in as
# compile definitions (HYMM_SOURCE_DIR, HYMM_BINARY_DIR). COST (ctest's property, on
# every test of the executable): a parallel ctest without timings of an earlier run (a
# fresh clone, CI) starts the costliest tests first, so the long end-to-end runs do not
# come last and run alone (clang sanitizer stage: 32.6 min with it, 31.3 min without, on a
# machine busy with other work both times: no gain measured yet).
function(hymm_add_test name)
    if(NOT HYMM_BUILD_TESTS)
        return()
    endif()
    cmake_parse_arguments(A "" "COST" "SOURCES;LINK_LIBRARIES;LABELS" ${ARGN})
    if(NOT A_COST)
        set(A_COST 0)
    endif()
    add_executable(${name} ${A_SOURCES})
    target_link_libraries(${name} PRIVATE ${A_LINK_LIBRARIES} GTest::gtest GTest::gtest_main)
    target_compile_definitions(${name} PRIVATE
        HYMM_SOURCE_DIR="${PROJECT_SOURCE_DIR}" HYMM_BINARY_DIR="${PROJECT_BINARY_DIR}")
    hymm_set_warnings(${name})
    set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tests)
    if(NOT A_LABELS)
        set(A_LABELS unit)
    endif()
    gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS "${A_LABELS}" COST ${A_COST})
endfunction()

# hymm_add_failure_test(NAME REGEX COMMAND...)
# ctest NAME runs COMMAND and passes only if it exits non-zero with output matching
# REGEX (cmake/expect_failure.cmake): an app given bad input must fail with a message
# saying what is wrong, not crash or succeed. Label 'app'.
function(hymm_add_failure_test name regex)
    if(NOT HYMM_BUILD_TESTS)
        return()
    endif()
    add_test(NAME ${name}
        COMMAND ${CMAKE_COMMAND} "-DREGEX=${regex}" "-DCMD=${ARGN}"
                -P ${PROJECT_SOURCE_DIR}/cmake/expect_failure.cmake)
    set_tests_properties(${name} PROPERTIES LABELS app)
endfunction()

# hymm_add_benchmark(NAME SOURCES ... LINK_LIBRARIES ...)
function(hymm_add_benchmark name)
    cmake_parse_arguments(A "" "" "SOURCES;LINK_LIBRARIES" ${ARGN})
    add_executable(${name} ${A_SOURCES})
    target_link_libraries(${name} PRIVATE ${A_LINK_LIBRARIES} benchmark::benchmark)
    target_compile_definitions(${name} PRIVATE HYMM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
    hymm_set_warnings(${name})
    set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/benchmarks)
endfunction()

# hymm_mrpt_opengl_sources(FILES...)
# Sources that construct mrpt::opengl objects. MRPT 2.5's CRenderizableShaderTriangles
# asks for 32-byte alignment that std::make_shared in MRPT's own inline Create() does not
# give it, so UBSan's alignment check fails inside MRPT's header code (a five-line program
# calling mrpt::opengl::CEllipsoid2D::Create() reproduces it with any -march). Those files
# are built without that one check; every other check stays on.
function(hymm_mrpt_opengl_sources)
    if(HYMM_SANITIZED)
        set_source_files_properties(${ARGN} PROPERTIES COMPILE_OPTIONS -fno-sanitize=alignment)
    endif()
endfunction()
