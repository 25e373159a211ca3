# `cmake --install`: headers, the four libraries, rttConfig.cmake / rttConfigVersion.cmake with
# the targets exported under rtt::, and pkg-config files. Each library has its own export file,
# so find_package(rtt) needs only the dependencies of the components it loads: rtt::core needs
# oneTBB (and Embree when built with it), never assimp, nlohmann-json or libpng
# (cmake/rttConfig.cmake.in).
include(CMakePackageConfigHelpers)

set(RTT_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/rtt)

install(DIRECTORY include/rtt DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(FILES ${PROJECT_BINARY_DIR}/include/rtt/version.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/rtt)

foreach(component core builtin_scenes scene render)
  install(TARGETS rtt_${component} EXPORT rtt-${component}-targets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(EXPORT rtt-${component}-targets NAMESPACE rtt:: DESTINATION ${RTT_CMAKE_DIR})
endforeach()
install(TARGETS rtt_all EXPORT rtt-all-targets)
install(EXPORT rtt-all-targets NAMESPACE rtt:: DESTINATION ${RTT_CMAKE_DIR})

configure_package_config_file(cmake/rttConfig.cmake.in ${PROJECT_BINARY_DIR}/rttConfig.cmake
  INSTALL_DESTINATION ${RTT_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/rttConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)  # 0.x: a minor version may change the API
install(FILES ${PROJECT_BINARY_DIR}/rttConfig.cmake ${PROJECT_BINARY_DIR}/rttConfigVersion.cmake
  DESTINATION ${RTT_CMAKE_DIR})

# pkg-config: rtt-core (the tracers) and rtt (everything). Static builds list the libraries
# rtt's own depend on in Libs.private / Requires.private.
set(RTT_PC_EMBREE "")
if(RTT_HAVE_EMBREE)
  set(RTT_PC_EMBREE "-lembree3")
endif()
foreach(pc rtt-core rtt)
  configure_file(cmake/${pc}.pc.in ${PROJECT_BINARY_DIR}/${pc}.pc @ONLY)
  install(FILES ${PROJECT_BINARY_DIR}/${pc}.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
endforeach()
