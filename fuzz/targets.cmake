# The libFuzzer targets, included by fuzz/CMakeLists.txt in both of its forms: the standalone
# fuzz/ project and the main project's instrumented build (-DCW4D_BUILD_FUZZ=ON). The libraries
# they link (cw4d_complex; with CW4D_FUZZ_CLI also cw4d_cli and cw4d_render) come from the
# including project, instrumented for coverage (the standalone project: -fsanitize=fuzzer-no-link;
# the main project: 8-bit edge counters) and checked by ASan + UBSan; only the targets link
# libFuzzer's main.
foreach(target off g4mf scene spec nesting wythoff)
  add_executable(fuzz_${target} ${CMAKE_CURRENT_LIST_DIR}/fuzz_${target}.cpp)
  target_link_libraries(fuzz_${target} PRIVATE cw4d_complex)
  target_link_options(fuzz_${target} PRIVATE -fsanitize=fuzzer)
endforeach()

if(NOT CW4D_FUZZ_CLI)
  return()
endif()
# The command line as a function (cw4d::cli::run), the texture readers (slice patterns, PNG
# bytes) and the page of `cw4d view`.
add_executable(fuzz_cli ${CMAKE_CURRENT_LIST_DIR}/fuzz_cli.cpp)
target_link_libraries(fuzz_cli PRIVATE cw4d_cli)
add_executable(fuzz_texture ${CMAKE_CURRENT_LIST_DIR}/fuzz_texture.cpp)
target_link_libraries(fuzz_texture PRIVATE cw4d_render)
add_executable(fuzz_view ${CMAKE_CURRENT_LIST_DIR}/fuzz_view.cpp)
target_include_directories(fuzz_view PRIVATE ${CMAKE_CURRENT_LIST_DIR}/../apps/cw4d)
target_link_libraries(fuzz_view PRIVATE cw4d_cli)
foreach(target cli texture view)
  target_link_options(fuzz_${target} PRIVATE -fsanitize=fuzzer)
endforeach()
