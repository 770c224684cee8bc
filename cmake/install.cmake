# install.cmake: what `cmake --install BUILD --prefix P` puts under P.
#   include/retroprism/          the headers of the installed libraries, with the math core's
#                                .inc files and the parameter table (a renderer compiles the core
#                                into its own kernels through <retroprism/prism_core.h>)
#   lib/                         libretroprism_{node,batch,util,io,analysis}.a,
#                                position-independent
#   lib/cmake/retroprism/        retroprismConfig.cmake, its version file and the exported
#                                targets retroprism::node, ::batch, ::util, ::io, ::analysis
#                                (and ::osl, the OSL closure, where OSL was found)
#   lib/pkgconfig/               retroprism.pc (the node), retroprism-analysis.pc (the readers and
#                                photometry)
#   bin/retroprism               the command
#   share/retroprism/            its run-time data, where util/paths.h looks first
#                                (<exe>/../share/retroprism): the MaterialX library, examples and
#                                tool (with its lockfile and node_modules), the accuracy study's
#                                results and template, the example materials, documents, R_A
#                                tables, the standards' minimum R_A tables (examples/standards)
#                                and the consumer project, the generated GLSL variants, the OSL
#                                shaders (osl/shaders) and the opt-in MaterialX library
#                                of the OSL closure (materialx/rp_pbrlib_closure)
#   lib/python3.X/site-packages/ the Python module (python/CMakeLists.txt)
# The CMake package and the pkg-config files locate the prefix from their own folder, so an
# installed tree may be moved.
include(CMakePackageConfigHelpers)

set(RP_INSTALLED_LIBRARIES retroprism_node retroprism_batch retroprism_util retroprism_io
                           retroprism_analysis)
# A renderer's plug-in (a shared library) and the Python module link these static libraries.
set_target_properties(${RP_INSTALLED_LIBRARIES} PROPERTIES POSITION_INDEPENDENT_CODE ON)
foreach(target ${RP_INSTALLED_LIBRARIES})
  string(REPLACE "retroprism_" "" exportName ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${exportName})
endforeach()

set(RP_INCLUDE_DEST ${CMAKE_INSTALL_INCLUDEDIR}/retroprism)
set(RP_CMAKE_DEST ${CMAKE_INSTALL_LIBDIR}/cmake/retroprism)
set(RP_DATA_DEST ${CMAKE_INSTALL_DATADIR}/retroprism)

install(TARGETS ${RP_INSTALLED_LIBRARIES} EXPORT retroprismTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS retroprism RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

# Headers: flat in include/retroprism/, where their quoted includes of one another resolve. The
# bootstrap tables only serve tools/gen_tables.cpp.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/nodes/ DESTINATION ${RP_INCLUDE_DEST}
        FILES_MATCHING PATTERN "*.h" PATTERN "*.inc" PATTERN "*.def"
        PATTERN "prism_tables_bootstrap.inc" EXCLUDE)
foreach(folder util io analysis)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${folder}/ DESTINATION ${RP_INCLUDE_DEST}
          FILES_MATCHING PATTERN "*.h")
endforeach()

# Run-time data, at the paths util/paths.h and the commands ask for.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/materialx/rp_pbrlib ${PROJECT_SOURCE_DIR}/materialx/examples
        DESTINATION ${RP_DATA_DEST}/materialx)
install(FILES ${PROJECT_SOURCE_DIR}/materialx/tools/mx.cjs
              ${PROJECT_SOURCE_DIR}/materialx/tools/package.json
              ${PROJECT_SOURCE_DIR}/materialx/tools/package-lock.json
              ${PROJECT_SOURCE_DIR}/materialx/tools/.npmrc
        DESTINATION ${RP_DATA_DEST}/materialx/tools)
# MaterialX 1.39.4 as `npm ci` installed it (scripts/setup-debian.sh); without it the installed
# command runs everything but the materialx backend, and `npm ci` in the installed
# materialx/tools (from the lockfile) supplies it.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/materialx/tools/node_modules/
        DESTINATION ${RP_DATA_DEST}/materialx/tools/node_modules OPTIONAL)
install(FILES ${PROJECT_SOURCE_DIR}/docs/accuracy/results.csv
        DESTINATION ${RP_DATA_DEST}/docs/accuracy)
install(FILES ${PROJECT_SOURCE_DIR}/docs/accuracy.md.in DESTINATION ${RP_DATA_DEST}/docs)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples/materials ${PROJECT_SOURCE_DIR}/examples/documents
                  ${PROJECT_SOURCE_DIR}/examples/sheeting ${PROJECT_SOURCE_DIR}/examples/standards
                  ${PROJECT_SOURCE_DIR}/examples/consumer ${PROJECT_SOURCE_DIR}/examples/headlamps
        DESTINATION ${RP_DATA_DEST}/examples)
install(DIRECTORY ${RP_GENERATED_DIR}/glsl/ DESTINATION ${RP_DATA_DEST}/glsl)
# The look-dev page `retroprism view` serves (its static files) and its server, serve.py.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/web/ DESTINATION ${RP_DATA_DEST}/web
        FILES_MATCHING PATTERN "*.html" PATTERN "*.js" PATTERN "*.css" PATTERN "serve.py")

# The OSL closure (docs/osl.md): its generated shaders and opt-in MaterialX library always, and
# where OSL was found the library retroprism::osl with its header, in an export set of its own
# that retroprismConfig.cmake loads when the consumer finds OSL too.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/osl/shaders DESTINATION ${RP_DATA_DEST}/osl)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/materialx/rp_pbrlib_closure
        DESTINATION ${RP_DATA_DEST}/materialx)
if(TARGET retroprism_osl)
  set_target_properties(retroprism_osl PROPERTIES POSITION_INDEPENDENT_CODE ON EXPORT_NAME osl)
  install(TARGETS retroprism_osl EXPORT retroprismOslTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(FILES ${PROJECT_SOURCE_DIR}/osl/retroprism_closure.h DESTINATION ${RP_INCLUDE_DEST})
  install(EXPORT retroprismOslTargets NAMESPACE retroprism:: DESTINATION ${RP_CMAKE_DEST})
endif()

# The CMake package.
install(EXPORT retroprismTargets NAMESPACE retroprism:: DESTINATION ${RP_CMAKE_DEST})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/retroprismConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/retroprismConfig.cmake
                              INSTALL_DESTINATION ${RP_CMAKE_DEST})
# 0.x: a minor version may change the API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/retroprismConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/retroprismConfig.cmake
              ${PROJECT_BINARY_DIR}/retroprismConfigVersion.cmake
        DESTINATION ${RP_CMAKE_DEST})

# The pkg-config files, with the prefix relative to their own folder (${pcfiledir}).
file(RELATIVE_PATH RP_PC_TO_PREFIX /prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig /prefix)
string(REGEX REPLACE "/$" "" RP_PC_TO_PREFIX ${RP_PC_TO_PREFIX})
foreach(pc retroprism retroprism-analysis)
  configure_file(${CMAKE_CURRENT_LIST_DIR}/${pc}.pc.in ${PROJECT_BINARY_DIR}/${pc}.pc @ONLY)
  install(FILES ${PROJECT_BINARY_DIR}/${pc}.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
endforeach()
