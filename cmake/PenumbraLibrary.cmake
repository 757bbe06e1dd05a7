# The installable library: libpenumbra.so (every module's objects; their third-party dependencies
# stay private to it), the public headers, the CLI, and the CMake package that
# `find_package(Penumbra CONFIG REQUIRED)` + `target_link_libraries(app Penumbra::penumbra)` use.
# `add_subdirectory(penumbra)` gives the same Penumbra::penumbra target.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(penumbra_objects)
foreach(module ${penumbra_modules})
  list(APPEND penumbra_objects $<TARGET_OBJECTS:${module}>)
endforeach()
add_library(penumbra_shared SHARED ${penumbra_objects})
add_library(Penumbra::penumbra ALIAS penumbra_shared)
set_target_properties(penumbra_shared PROPERTIES
  OUTPUT_NAME penumbra EXPORT_NAME penumbra
  VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})
# The static modules only bring their third-party libraries here (their own objects are above).
target_link_libraries(penumbra_shared PRIVATE penumbra)
# What a consumer compiles with: the headers (the facade in include/, the few module headers it
# exposes under src/ while building, all under include/ once installed), the definition that
# gives glm the layout the library was compiled with, and the header-only libraries those headers
# include. No -march, warning or sanitizer flag crosses over.
target_include_directories(penumbra_shared INTERFACE
  $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include> $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/src>
  $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
target_compile_definitions(penumbra_shared INTERFACE GLM_FORCE_XYZW_ONLY)
target_link_libraries(penumbra_shared INTERFACE glm::glm nlohmann_json::nlohmann_json)
target_compile_features(penumbra_shared INTERFACE cxx_std_20)

# The module headers the public facade includes (and nothing else of src/): the scene types, the
# visibility and masks, the method registry and its options, the error metrics.
set(penumbra_public_module_headers
  core/error.hpp core/image.hpp core/light_samples.hpp core/math.hpp core/stats.hpp
  render/gbuffer.hpp render/visibility.hpp
  scene/camera.hpp scene/light.hpp scene/material.hpp scene/mesh.hpp scene/model_scene.hpp
  scene/animation.hpp scene/scene.hpp scene/scene_file.hpp scene/texture.hpp
  shadows/method.hpp shadows/registry.hpp
  metrics/error_metrics.hpp)

install(TARGETS penumbra_shared EXPORT PenumbraTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS penumbra_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
foreach(header ${penumbra_public_module_headers})
  get_filename_component(dir ${header} DIRECTORY)
  install(FILES ${PROJECT_SOURCE_DIR}/src/penumbra/${header}
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/penumbra/${dir})
endforeach()

set(penumbra_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/Penumbra)
install(EXPORT PenumbraTargets NAMESPACE Penumbra:: DESTINATION ${penumbra_cmake_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/PenumbraConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/PenumbraConfig.cmake
                              INSTALL_DESTINATION ${penumbra_cmake_dir})
# 0.x: a minor version may change the API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/PenumbraConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/PenumbraConfig.cmake ${PROJECT_BINARY_DIR}/PenumbraConfigVersion.cmake
        DESTINATION ${penumbra_cmake_dir})
