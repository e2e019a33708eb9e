# Third-party libraries of the sim library, found the same way by this
# project and by programs that use an installed loosehair (loosehairConfig).
# All of them come from Debian packages (scripts/install-deps.sh).
include(CMakeFindDependencyMacro)
find_dependency(glm)
find_dependency(Threads)
find_dependency(OpenMesh)   # OBJ, PLY, OFF, STL meshes
find_dependency(TinyGLTF)   # glTF and GLB meshes
find_dependency(Eigen3)     # sparse solve of the harmonic scalp map
find_dependency(TBB)        # OpenVDB's threads
find_dependency(Imath)      # OpenVDB's half floats
# Debian's FindOpenVDB module asks for Boost components that its package does
# not install, so the library is imported directly.
if(NOT TARGET loosehair_deps::openvdb)
  find_library(LOOSEHAIR_OPENVDB_LIBRARY NAMES openvdb REQUIRED)
  find_path(LOOSEHAIR_OPENVDB_INCLUDE openvdb/openvdb.h REQUIRED)
  add_library(loosehair_deps::openvdb UNKNOWN IMPORTED)
  set_target_properties(loosehair_deps::openvdb PROPERTIES
    IMPORTED_LOCATION "${LOOSEHAIR_OPENVDB_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${LOOSEHAIR_OPENVDB_INCLUDE}"
    INTERFACE_LINK_LIBRARIES "TBB::tbb;Imath::Imath")
endif()
if(NOT TARGET loosehair_deps::stb)
  find_library(LOOSEHAIR_STB_LIBRARY NAMES stb REQUIRED)  # image reading (hair-length maps)
  add_library(loosehair_deps::stb UNKNOWN IMPORTED)
  set_target_properties(loosehair_deps::stb PROPERTIES IMPORTED_LOCATION "${LOOSEHAIR_STB_LIBRARY}")
endif()
