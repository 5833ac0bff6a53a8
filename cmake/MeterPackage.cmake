# Install rules and the Debian packages (docs/deploy.md). Four packages by role:
#   meter-controller  the controller, its systemd unit, user, configuration, the demo vehicle and log
#   meter-view        the view, its systemd unit, user, configuration, the converted cluster scene
#   meter-tools       the offline and test engineer's tools (convert, package, verify, calibrate,
#                     linkdump, linkplay, preview) and the cluster scene's sources
#   meter-dev         the protocol library an integrator embeds: headers, static library, a CMake
#                     package (find_package(meter)) and a pkg-config file (meter-protocol)
# The installed programs read no path of the source or build tree: every file they need is given on
# their command line, and the units' configuration names the installed copies under the prefix
# configured here. The texts' font travels in the scene package: the converter (meter-tools) reads
# DejaVu Sans from the Debian package fonts-dejavu-core, its dependency; the view opens no font.
#
# cmake --install BUILD installs every component; DESTDIR=ROOT cmake --install BUILD into a root;
# `cpack --config BUILD/CPackConfig.cmake` (or `ninja -C BUILD package`) writes the four .deb files.

# The deployed layout is Debian's: a prefix of /usr unless one is asked for. CMake's default
# (/usr/local) is replaced once per tree, also in a tree configured before these rules existed.
if(NOT METER_INSTALL_PREFIX_CHOSEN AND (CMAKE_INSTALL_PREFIX_INITIALIZED_TO_DEFAULT OR CMAKE_INSTALL_PREFIX STREQUAL "/usr/local"))
  set(CMAKE_INSTALL_PREFIX /usr CACHE PATH "Install prefix (the Debian packages' is /usr)" FORCE)
endif()
set(METER_INSTALL_PREFIX_CHOSEN ON CACHE INTERNAL "the install prefix is the tree's own choice from here on")
include(GNUInstallDirs)

# Under /usr the configuration lives in /etc and the units where Debian 12's systemd ships its own;
# under another prefix both stay inside it.
if(CMAKE_INSTALL_PREFIX STREQUAL "/usr")
  set(METER_UNIT_DIR /lib/systemd/system)
else()
  set(METER_UNIT_DIR lib/systemd/system)
endif()
set(METER_CONF_DIR ${CMAKE_INSTALL_FULL_SYSCONFDIR}/meter)
set(METER_DATA_DIR ${CMAKE_INSTALL_DATADIR}/meter)
set(METER_FULL_DATA_DIR ${CMAKE_INSTALL_FULL_DATADIR}/meter)
set(_deploy ${PROJECT_SOURCE_DIR}/deploy)
set(_staged ${PROJECT_BINARY_DIR}/deploy)

# --- programs, by role -------------------------------------------------------------------------
install(TARGETS meter-controller RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT controller)
install(TARGETS meter-view RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT view)
# (A target build, METER_RUNTIME_ONLY, has no meter-convert, meter-calibrate or meter-preview: they run
# on the host, docs/targets.md.)
set(METER_TOOL_PROGRAMS)
foreach(_tool meter-convert meter-package meter-verify meter-calibrate meter-linkdump meter-linkplay meter-preview)
  if(TARGET ${_tool})
    list(APPEND METER_TOOL_PROGRAMS ${_tool})
  endif()
endforeach()
install(TARGETS ${METER_TOOL_PROGRAMS} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT tools)

# --- the shipped data ----------------------------------------------------------------------------
install(FILES ${PROJECT_SOURCE_DIR}/controller/vehicles/demo/demo.dbc ${PROJECT_SOURCE_DIR}/controller/vehicles/demo/demo.map
        DESTINATION ${METER_DATA_DIR}/vehicles/demo COMPONENT controller)
install(FILES ${PROJECT_SOURCE_DIR}/vcan/logs/demo-drive.log DESTINATION ${METER_DATA_DIR}/logs COMPONENT controller)
# The built-in catalog, as a file to read and to start a --catalog of one's own from.
install(FILES ${PROJECT_SOURCE_DIR}/protocol/catalog/signals.vss.json DESTINATION ${METER_DATA_DIR}/catalog
        COMPONENT controller)
install(FILES ${PROJECT_SOURCE_DIR}/scenes/cluster/cluster.glb ${PROJECT_SOURCE_DIR}/scenes/cluster/cluster.scene.json
              ${PROJECT_SOURCE_DIR}/scenes/cluster/cluster.groups.json
        DESTINATION ${METER_DATA_DIR}/scenes/cluster COMPONENT tools)

# The cluster scene converted by the build's own converter, so the view's package needs no converter;
# a target build's by the host build's (the package format is the same on every architecture).
set(METER_SHIPPED_SCENE ${_staged}/scenes/cluster.msp)
if(TARGET meter-convert)
  set(_convert meter-convert)
else()
  set(METER_HOST_CONVERT "" CACHE FILEPATH "A host build's meter-convert (a target build has none of its own)")
  if(NOT EXISTS "${METER_HOST_CONVERT}")
    message(FATAL_ERROR "meter: a target build converts its scenes with a host build's meter-convert: "
                        "configure with -DMETER_HOST_CONVERT=HOST_BUILD/bin/meter-convert (scripts/cross-build does)")
  endif()
  set(_convert ${METER_HOST_CONVERT})
endif()
add_custom_command(OUTPUT ${METER_SHIPPED_SCENE}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${_staged}/scenes
  COMMAND ${_convert} ${PROJECT_SOURCE_DIR}/scenes/cluster/cluster.glb
          --config ${PROJECT_SOURCE_DIR}/scenes/cluster/cluster.scene.json -o ${METER_SHIPPED_SCENE} -q
  DEPENDS ${_convert} ${PROJECT_SOURCE_DIR}/scenes/cluster/cluster.glb
          ${PROJECT_SOURCE_DIR}/scenes/cluster/cluster.scene.json ${PROJECT_SOURCE_DIR}/scenes/cluster/cluster.groups.json
  COMMENT "Converting the shipped cluster scene for meter-view's package"
  VERBATIM)
add_custom_target(meter_shipped_scene ALL DEPENDS ${METER_SHIPPED_SCENE})
install(FILES ${METER_SHIPPED_SCENE} DESTINATION ${METER_DATA_DIR}/scenes COMPONENT view)

# --- services: units, users, configuration ---------------------------------------------------------
foreach(_role controller view)
  configure_file(${_deploy}/systemd/meter-${_role}.service ${_staged}/systemd/meter-${_role}.service @ONLY)
  configure_file(${_deploy}/etc/${_role}.conf ${_staged}/etc/${_role}.conf @ONLY)
  install(FILES ${_staged}/systemd/meter-${_role}.service DESTINATION ${METER_UNIT_DIR} COMPONENT ${_role})
  install(FILES ${_deploy}/systemd/meter-${_role}.sysusers DESTINATION ${CMAKE_INSTALL_PREFIX}/lib/sysusers.d
          RENAME meter-${_role}.conf COMPONENT ${_role})
  install(FILES ${_staged}/etc/${_role}.conf DESTINATION ${METER_CONF_DIR} COMPONENT ${_role})
endforeach()

# --- manuals, copyright and changelog (compressed as Debian's policy asks) ------------------------
set(_man_role_meter-controller controller)
set(_man_role_meter-view view)
set(_manuals)
foreach(_prog meter-controller meter-view ${METER_TOOL_PROGRAMS})
  set(_gz ${_staged}/man/${_prog}.1.gz)
  add_custom_command(OUTPUT ${_gz}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${_staged}/man
    COMMAND sh -c "gzip -9nc \"$0\" > \"$1\"" ${_deploy}/man/${_prog}.1 ${_gz}
    DEPENDS ${_deploy}/man/${_prog}.1 VERBATIM)
  list(APPEND _manuals ${_gz})
  set(_role tools)
  if(DEFINED _man_role_${_prog})
    set(_role ${_man_role_${_prog}})
  endif()
  install(FILES ${_gz} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 COMPONENT ${_role})
endforeach()
set(_changelog ${_staged}/changelog.gz)
add_custom_command(OUTPUT ${_changelog}
  COMMAND sh -c "gzip -9nc \"$0\" > \"$1\"" ${_deploy}/debian/changelog ${_changelog}
  DEPENDS ${_deploy}/debian/changelog VERBATIM)
add_custom_target(meter_manuals ALL DEPENDS ${_manuals} ${_changelog})
foreach(_role controller view tools dev)
  install(FILES ${_deploy}/debian/copyright ${_changelog} DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/meter-${_role}
          COMPONENT ${_role})
endforeach()

# --- the development kit: the protocol library ----------------------------------------------------
install(TARGETS meter_protocol ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/protocol/include/meter DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT dev)
include(CMakePackageConfigHelpers)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/meterConfig.cmake.in ${_staged}/meterConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/meter PATH_VARS CMAKE_INSTALL_INCLUDEDIR CMAKE_INSTALL_LIBDIR)
write_basic_package_version_file(${_staged}/meterConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${_staged}/meterConfig.cmake ${_staged}/meterConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/meter COMPONENT dev)
configure_file(${PROJECT_SOURCE_DIR}/cmake/meter-protocol.pc.in ${_staged}/meter-protocol.pc @ONLY)
install(FILES ${_staged}/meter-protocol.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT dev)

# --- CPack: one Debian package a role -------------------------------------------------------------
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME meter)
set(CPACK_PACKAGE_VENDOR "meter developers")
set(CPACK_PACKAGE_CONTACT "meter developers <meter@example.com>")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "two-process 3D instrument cluster")
set(CPACK_PACKAGE_DIRECTORY ${PROJECT_BINARY_DIR}/packages)
# Absolute destinations (/etc/meter, /lib/systemd/system) go into the package through DESTDIR.
set(CPACK_SET_DESTDIR ON)
set(CPACK_INSTALL_PREFIX ${CMAKE_INSTALL_PREFIX})
set(CPACK_STRIP_FILES ON)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL controller view tools dev)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION misc)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
# The libraries each program links, with their versions, from dpkg-shlibdeps; what is opened at run
# time (the GL drivers; the converter's font) is stated below.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_COMPRESSION_TYPE gzip)

set(CPACK_DEBIAN_CONTROLLER_PACKAGE_NAME meter-controller)
set(CPACK_DEBIAN_CONTROLLER_PACKAGE_RECOMMENDS systemd)
set(CPACK_COMPONENT_CONTROLLER_DESCRIPTION
    "instrument cluster's vehicle-control process\nmeter-controller reads CAN (SocketCAN, candump logs) or Modbus, decodes it\nwith a DBC, conditions the signals and publishes the cluster state to\nmeter-view; with its systemd unit (watchdog, sandbox), user, configuration\nin /etc/meter and the demo vehicle and drive log.")
set(CPACK_DEBIAN_VIEW_PACKAGE_NAME meter-view)
set(CPACK_DEBIAN_VIEW_PACKAGE_DEPENDS "libegl-mesa0, libgl1-mesa-dri")
set(CPACK_DEBIAN_VIEW_PACKAGE_RECOMMENDS "systemd, meter-controller (= ${PROJECT_VERSION})")
set(CPACK_COMPONENT_VIEW_DESCRIPTION
    "instrument cluster's graphics process\nmeter-view renders the cluster scene offscreen (EGL or OSMesa) from the\nstate the controller publishes, checks its safety regions and dumps frames;\nwith its systemd unit (watchdog, sandbox), user, configuration in\n/etc/meter and the converted cluster scene.")
set(CPACK_DEBIAN_TOOLS_PACKAGE_NAME meter-tools)
set(CPACK_DEBIAN_TOOLS_PACKAGE_DEPENDS "fonts-dejavu-core, libegl-mesa0, libgl1-mesa-dri")
set(CPACK_COMPONENT_TOOLS_DESCRIPTION
    "instrument cluster's offline and test tools\nmeter-convert (glTF + scene config to a scene package), meter-package,\nmeter-verify, meter-calibrate, meter-linkdump, meter-linkplay and the\nartist's meter-preview, with the cluster scene's sources.")
set(CPACK_DEBIAN_DEV_PACKAGE_NAME meter-dev)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
# The static library's own dependency (the link's MAC) and what its pkg-config file asks for.
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS "libsodium-dev, pkg-config")
set(CPACK_COMPONENT_DEV_DESCRIPTION
    "instrument cluster's link library, development kit\nThe protocol library both meter processes share (signal catalog and table,\nwire format, transports, the link's two ends, recordings): C++20 headers,\na static library, a CMake package (find_package(meter), target\nmeter::protocol) and a pkg-config file (meter-protocol).")

# The service packages make their user and tell systemd of their unit (deploy/debian/).
foreach(_role controller view)
  string(TOUPPER ${_role} _ROLE)
  set(UNIT meter-${_role}.service)
  set(SYSUSERS ${CMAKE_INSTALL_PREFIX}/lib/sysusers.d/meter-${_role}.conf)
  foreach(_script postinst prerm postrm)
    configure_file(${_deploy}/debian/service.${_script}.in ${_staged}/debian/${_role}/${_script} @ONLY)
    file(CHMOD ${_staged}/debian/${_role}/${_script} PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE
         GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)
  endforeach()
  file(WRITE ${_staged}/debian/${_role}/conffiles "${METER_CONF_DIR}/${_role}.conf\n")
  set(CPACK_DEBIAN_${_ROLE}_PACKAGE_CONTROL_EXTRA
      ${_staged}/debian/${_role}/postinst ${_staged}/debian/${_role}/prerm ${_staged}/debian/${_role}/postrm
      ${_staged}/debian/${_role}/conffiles)
  set(CPACK_DEBIAN_${_ROLE}_PACKAGE_CONTROL_STRICT_PERMISSION ON)
endforeach()
include(CPack)
