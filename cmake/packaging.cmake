# Debian packages made by `cpack -G DEB` from the install components (CMakeLists.txt):
#   parity      bin/parity and share/parity; the drivers it renders with here (Mesa's llvmpipe
#               and lavapipe) are dependencies, so that `apt install ./parity_*.deb` on a fresh
#               Debian 12 is enough to run `parity run`; libraries found by dpkg-shlibdeps.
#   parity-dev  the static libraries, headers and CMake package; depends on the -dev packages
#               find_package(parity) looks for.
# cpack packages what the build made (scripts/package-check.sh builds first) instead of building
# every target, tests included, on the way.
set(CMAKE_SKIP_INSTALL_ALL_DEPENDENCY ON)
set(CPACK_PACKAGE_NAME parity)
set(CPACK_PACKAGE_VENDOR "parity")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "cross-platform shader and technique test harness (OpenGL 4.5 and Vulkan 1.3)")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_INSTALL_DIRECTORY parity)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_GENERATOR DEB)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL runtime development)
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "parity maintainers <parity@localhost>")
set(CPACK_DEBIAN_PACKAGE_SECTION devel)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)

set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME parity)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_DEPENDS "mesa-vulkan-drivers, libgl1-mesa-dri, libegl-mesa0")
# Loaded with dlopen when asked for: OSMesa (--gl-provider osmesa), GLFW (parity view), the
# Vulkan validation layer (--debug).
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SUGGESTS "libosmesa6, libglfw3, vulkan-validationlayers")

set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_NAME parity-dev)
set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_DEPENDS
    "parity (= ${PROJECT_VERSION}), cmake, pkg-config, glslang-dev, spirv-tools, libglm-dev, libvulkan-dev, \
nlohmann-json3-dev, libcli11-dev, libtinygltf-dev, libtinyobjloader-dev, libopenimageio-dev, \
libspirv-cross-c-shared-dev, libegl-dev")
set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_SHLIBDEPS OFF)  # static libraries only

include(CPack)
