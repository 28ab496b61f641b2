# ctest driver of the consumer project (tests/consumer/CMakeLists.txt):
#   cmake -DMODE=install -DBUILD=<cw4d build dir> -DPREFIX=<dir> -P run.cmake
#     installs cw4d into PREFIX (the default install component: libraries, headers, package
#     config; not the Python package) and checks that no installed header includes OpenMesh,
#     CGAL or TetGen;
#   cmake -DMODE=consume -DPREFIX=<dir> -DWORK=<dir> -DCOMPONENTS=section|tetra|all
#         -DCXX=... -DCXX_FLAGS=... -DLINKER_FLAGS=... -DBUILD_TYPE=... -P run.cmake
#     configures, builds and runs the consumer against PREFIX in a fresh WORK directory.
cmake_minimum_required(VERSION 3.20)

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status)
  if(NOT status EQUAL 0)
    string(REPLACE ";" " " line "${ARGN}")
    message(FATAL_ERROR "failed (${status}): ${line}")
  endif()
endfunction()

if(MODE STREQUAL "install")
  file(REMOVE_RECURSE "${PREFIX}")
  run(${CMAKE_COMMAND} --install "${BUILD}" --prefix "${PREFIX}" --component Unspecified)
  file(GLOB_RECURSE headers "${PREFIX}/include/cw4d/*")
  if(NOT headers)
    message(FATAL_ERROR "no header installed under ${PREFIX}/include/cw4d")
  endif()
  foreach(header IN LISTS headers)
    file(STRINGS "${header}" heavy REGEX "^[ \t]*#[ \t]*include[ \t]*[<\"](OpenMesh/|CGAL/|tetgen)")
    if(heavy)
      message(FATAL_ERROR "installed header ${header} includes ${heavy}")
    endif()
  endforeach()
elseif(MODE STREQUAL "consume")
  set(dir "${WORK}/${COMPONENTS}")
  file(REMOVE_RECURSE "${dir}")
  set(args -S "${CMAKE_CURRENT_LIST_DIR}" -B "${dir}" -G Ninja "-DCMAKE_PREFIX_PATH=${PREFIX}"
    "-DCMAKE_CXX_COMPILER=${CXX}" "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}"
    "-DCMAKE_EXE_LINKER_FLAGS=${LINKER_FLAGS}" "-DCMAKE_BUILD_TYPE=${BUILD_TYPE}")
  if(LAUNCHER)
    list(APPEND args "-DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER}")
  endif()
  if(COMPONENTS STREQUAL "section" OR COMPONENTS STREQUAL "tetra")
    # A consumer of cw4d::section or cw4d::tetra must not need these: make them unfindable.
    list(APPEND args -DCW4D_COMPONENTS=${COMPONENTS})
    foreach(package OpenMesh CGAL TinyGLTF glm)
      list(APPEND args -DCMAKE_DISABLE_FIND_PACKAGE_${package}=ON)
    endforeach()
  endif()
  run(${CMAKE_COMMAND} ${args})
  run(${CMAKE_COMMAND} --build "${dir}")
  run("${dir}/consumer")
else()
  message(FATAL_ERROR "run.cmake: MODE must be install or consume")
endif()
