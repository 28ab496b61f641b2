# cw4d_settings and cw4d_add_library, shared by the main project and the fuzz/ project (which
# builds complex/ alone with clang).
# Common settings for every cw4d target (no global CMAKE_CXX_FLAGS).
add_library(cw4d_settings INTERFACE)
target_compile_features(cw4d_settings INTERFACE cxx_std_20)
if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  target_compile_options(cw4d_settings INTERFACE -Wall -Wextra -Wpedantic
    $<$<BOOL:${CW4D_WERROR}>:-Werror>)
endif()
# GCC 12 reports a false -Wrestrict inside libstdc++'s std::string wherever an append of a short
# literal is inlined ("text" + std::string&&, char_traits::copy; GCC bug 105329, fixed in 13): it
# strikes whichever file the optimiser happens to inline it in, so it is off for GCC 12 as a whole
# rather than file by file.
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_GREATER_EQUAL 12
   AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  target_compile_options(cw4d_settings INTERFACE -Wno-restrict)
endif()

include(GNUInstallDirs)

# cw4d_add_library(NAME SOURCES src... LINK dep...): the library cw4d_NAME (alias cw4d::NAME)
# with its public headers in NAME/include/cw4d/NAME.
function(cw4d_add_library name)
  cmake_parse_arguments(L "" "" "SOURCES;LINK" ${ARGN})
  add_library(cw4d_${name} ${L_SOURCES})
  add_library(cw4d::${name} ALIAS cw4d_${name})
  set_target_properties(cw4d_${name} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME cw4d_${name})
  target_include_directories(cw4d_${name} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(cw4d_${name} PUBLIC ${L_LINK})
endfunction()
