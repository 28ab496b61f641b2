# The header-only dependencies of complex/ and section/ for the emscripten build, taken from the
# Debian packages (libeigen3-dev, nlohmann-json3-dev). Their CMake configs would add
# -I/usr/include, which puts the host's C library in front of emscripten's: instead each
# library's own folder is exposed (Eigen's include/eigen3, a link to nlohmann/ alone).
find_path(CW4D_EIGEN_INCLUDE_DIR Eigen/Core PATHS /usr/include/eigen3 NO_CMAKE_FIND_ROOT_PATH
  NO_DEFAULT_PATH REQUIRED)
add_library(Eigen3::Eigen INTERFACE IMPORTED)
target_include_directories(Eigen3::Eigen SYSTEM INTERFACE ${CW4D_EIGEN_INCLUDE_DIR})

find_path(CW4D_NLOHMANN_DIR nlohmann/json.hpp PATHS /usr/include NO_CMAKE_FIND_ROOT_PATH
  NO_DEFAULT_PATH REQUIRED)
set(CW4D_HOST_HEADERS ${CMAKE_BINARY_DIR}/host-headers)
file(MAKE_DIRECTORY ${CW4D_HOST_HEADERS})
file(CREATE_LINK ${CW4D_NLOHMANN_DIR}/nlohmann ${CW4D_HOST_HEADERS}/nlohmann SYMBOLIC)
add_library(nlohmann_json::nlohmann_json INTERFACE IMPORTED)
target_include_directories(nlohmann_json::nlohmann_json SYSTEM INTERFACE ${CW4D_HOST_HEADERS})

# The viewer slices on the page's one thread (no SharedArrayBuffer needed): std::thread is not
# linked in, and section/ is only ever called with one thread.
add_library(Threads::Threads INTERFACE IMPORTED)

# libc++ 14 has no floating-point std::from_chars, which complex/ parses numbers with.
add_compile_options(-include ${CMAKE_CURRENT_LIST_DIR}/src/from_chars_double.hpp)

# C++ exceptions carry cw4d's error messages to the page.
add_compile_options(-fexceptions)
add_link_options(-fexceptions)
