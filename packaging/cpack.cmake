# Installation and the Debian packages (CPack): `cpack -G DEB` in a build folder writes
# atelier-cli_VERSION_ARCH.deb (the command line, the samples and presets: no Qt, for batch
# machines) and atelier_VERSION_ARCH.deb (the desktop application, which depends on it).
# packaging/deb/build-and-check.sh builds, installs and smoke-tests both (CI runs it).
set(CMAKE_INSTALL_DOCDIR share/doc/atelier-cli)
include(GNUInstallDirs)

install(TARGETS atelier-cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT cli)
# Debian installs manual pages compressed (gzip -9n: no name or time stamp in the header).
set(ATELIER_MAN_PAGE "${CMAKE_BINARY_DIR}/packaging/atelier-cli.1.gz")
add_custom_command(OUTPUT "${ATELIER_MAN_PAGE}"
  COMMAND ${CMAKE_COMMAND} -E make_directory "${CMAKE_BINARY_DIR}/packaging"
  COMMAND gzip -9n -c "${PROJECT_SOURCE_DIR}/packaging/man/atelier-cli.1" > "${ATELIER_MAN_PAGE}"
  DEPENDS "${PROJECT_SOURCE_DIR}/packaging/man/atelier-cli.1"
  VERBATIM)
add_custom_target(atelier_man_page ALL DEPENDS "${ATELIER_MAN_PAGE}")
install(FILES "${ATELIER_MAN_PAGE}" DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 COMPONENT cli)
# The sample garments and the fabric presets (built into the program too; the file documents
# them), the scenes, and a batch manifest example.
install(DIRECTORY "${PROJECT_SOURCE_DIR}/assets/garments/"
        DESTINATION ${CMAKE_INSTALL_DATADIR}/atelier/garments COMPONENT cli
        FILES_MATCHING PATTERN "*.atelier")
install(FILES "${PROJECT_SOURCE_DIR}/assets/materials/fabrics.json"
        DESTINATION ${CMAKE_INSTALL_DATADIR}/atelier/materials COMPONENT cli)
install(DIRECTORY "${PROJECT_SOURCE_DIR}/assets/scenes/"
        DESTINATION ${CMAKE_INSTALL_DATADIR}/atelier/scenes COMPONENT cli)
install(FILES "${PROJECT_SOURCE_DIR}/packaging/slurm/atelier-array.sbatch"
              "${PROJECT_SOURCE_DIR}/packaging/k8s/atelier-indexed-job.yaml"
        DESTINATION ${CMAKE_INSTALL_DATADIR}/atelier/batch COMPONENT cli)
# The .atelier MIME type, so that file managers know project files.
install(FILES "${PROJECT_SOURCE_DIR}/packaging/deb/atelier-mime.xml"
        DESTINATION ${CMAKE_INSTALL_DATADIR}/mime/packages RENAME atelier.xml COMPONENT cli)
install(FILES "${PROJECT_SOURCE_DIR}/README.md" "${PROJECT_SOURCE_DIR}/packaging/deb/copyright"
        DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT cli)

# The desktop application: the program, its desktop entry (opening .atelier files) and icon.
install(TARGETS atelier RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT gui)
install(FILES "${PROJECT_SOURCE_DIR}/packaging/deb/atelier.desktop"
        DESTINATION ${CMAKE_INSTALL_DATADIR}/applications COMPONENT gui)
install(FILES "${PROJECT_SOURCE_DIR}/packaging/deb/atelier.svg"
        DESTINATION ${CMAKE_INSTALL_DATADIR}/icons/hicolor/scalable/apps COMPONENT gui)
install(FILES "${PROJECT_SOURCE_DIR}/packaging/deb/copyright"
        DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/atelier COMPONENT gui)

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME atelier)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL cli gui)
set(CPACK_DEBIAN_CLI_PACKAGE_NAME atelier-cli)
set(CPACK_DEBIAN_GUI_PACKAGE_NAME atelier)
set(CPACK_PACKAGE_VENDOR "Atelier")
set(CPACK_PACKAGE_CONTACT "Atelier developers <atelier@localhost>")
set(CPACK_COMPONENT_CLI_DESCRIPTION "garment design: cloth simulation, draping and pictures, headless
Atelier drapes sewing patterns on a body with a cloth simulation engine and writes the draped
garment as a mesh, a report and pictures (headless OpenGL through EGL). This package holds the
command line, atelier-cli, with batch scripts for Slurm and Kubernetes, the sample garments and
the fabric presets.")
set(CPACK_COMPONENT_GUI_DESCRIPTION "garment design: the desktop application
Atelier's window: the garment's pattern and its drape side by side, the drape running on a
worker thread while the 3D view follows it.")
set(CPACK_PACKAGE_INSTALL_DIRECTORY atelier)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_PACKAGE_HOMEPAGE "https://atelier.invalid")
set(CPACK_DEBIAN_PACKAGE_LICENSE "GPL-3+")
# Shared libraries the program links to, as dpkg-shlibdeps finds them, and the EGL/OpenGL
# drivers libepoxy opens at run time (not visible to dpkg-shlibdeps).
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_CLI_PACKAGE_DEPENDS "libegl1, libegl-mesa0, libgl1-mesa-dri, libopengl0")
set(CPACK_DEBIAN_CLI_PACKAGE_SUGGESTS "slurm-client")
set(CPACK_DEBIAN_GUI_PACKAGE_DEPENDS "atelier-cli (= ${PROJECT_VERSION}), libegl1, libegl-mesa0, libgl1-mesa-dri, libopengl0")
set(CPACK_DEBIAN_GUI_PACKAGE_SECTION graphics)
set(CPACK_STRIP_FILES ON)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
include(CPack)
