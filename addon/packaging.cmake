# Packaging of the Blender add-on.
#
# Included (OPTIONAL) at the end of the top-level CMakeLists.txt, it defines
#   cmake --build build --target addon_zip
# which writes build/dist/developable_mesh-<version>-linux-x64.zip holding one
# folder, developable_mesh/, with the Python package (and its core/ subpackage), blender_manifest.toml and
# the native library. The library needs only the C/C++ runtimes; should it
# ever link anything else, that is copied beside it (and the build fails on a
# dependency it cannot resolve).
#
# The same file is also the build-time script (cmake -P) that stages and zips.

set(_ADDON_FOLDER developable_mesh)
# Libraries every Linux system (and Blender) has: never bundled.
set(_ADDON_SYSTEM_LIBS
  "^linux-vdso" "^ld-linux" "^libc\\.so" "^libm\\.so" "^libstdc\\+\\+\\.so" "^libgcc_s\\.so"
  "^libpthread\\.so" "^libdl\\.so" "^librt\\.so")

if(CMAKE_SCRIPT_MODE_FILE)
  # ---- build-time script: -DSOURCE_DIR -DSTAGE_DIR -DDIST_DIR -DLIBRARY -DVERSION ----
  foreach(v SOURCE_DIR STAGE_DIR DIST_DIR LIBRARY VERSION)
    if(NOT DEFINED ${v})
      message(FATAL_ERROR "packaging.cmake: ${v} not set")
    endif()
  endforeach()
  set(folder "${STAGE_DIR}/${_ADDON_FOLDER}")
  file(REMOVE_RECURSE "${STAGE_DIR}")
  file(MAKE_DIRECTORY "${folder}" "${DIST_DIR}")

  file(GLOB py_files "${SOURCE_DIR}/addon/*.py")
  file(COPY ${py_files} DESTINATION "${folder}")
  file(GLOB core_files "${SOURCE_DIR}/addon/core/*.py")
  file(COPY ${core_files} DESTINATION "${folder}/core")
  file(COPY "${SOURCE_DIR}/blender_manifest.toml" DESTINATION "${folder}")
  if(EXISTS "${SOURCE_DIR}/LICENSE")
    file(COPY "${SOURCE_DIR}/LICENSE" DESTINATION "${folder}")
  endif()

  get_filename_component(lib_name "${LIBRARY}" NAME)
  configure_file("${LIBRARY}" "${folder}/${lib_name}" COPYONLY)

  file(GET_RUNTIME_DEPENDENCIES
    LIBRARIES "${LIBRARY}"
    RESOLVED_DEPENDENCIES_VAR deps
    UNRESOLVED_DEPENDENCIES_VAR missing
    PRE_EXCLUDE_REGEXES ${_ADDON_SYSTEM_LIBS}
    POST_EXCLUDE_REGEXES ".*/ld-linux[^/]*$")
  if(missing)
    message(FATAL_ERROR "addon_zip: unresolved dependencies of ${lib_name}: ${missing}")
  endif()
  foreach(dep IN LISTS deps)
    get_filename_component(dep_name "${dep}" NAME)
    set(skip FALSE)
    foreach(rx IN LISTS _ADDON_SYSTEM_LIBS)
      if(dep_name MATCHES "${rx}")
        set(skip TRUE)
      endif()
    endforeach()
    if(NOT skip)
      # Follows symlinks: the file is stored under the name the loader asks for.
      configure_file("${dep}" "${folder}/${dep_name}" COPYONLY)
      message(STATUS "addon_zip: bundling ${dep_name} (${dep})")
    endif()
  endforeach()

  set(zip "${DIST_DIR}/${_ADDON_FOLDER}-${VERSION}-linux-x64.zip")
  file(GLOB old_zips "${DIST_DIR}/${_ADDON_FOLDER}-*.zip")
  if(old_zips)
    file(REMOVE ${old_zips})
  endif()
  execute_process(
    COMMAND "${CMAKE_COMMAND}" -E tar cf "${zip}" --format=zip "${_ADDON_FOLDER}"
    WORKING_DIRECTORY "${STAGE_DIR}"
    RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "addon_zip: zipping failed (${rc})")
  endif()
  message(STATUS "addon_zip: wrote ${zip}")
  return()
endif()

# ---- configure time: the target ----
if(TARGET developable_engine)
  file(GLOB _ADDON_PY CONFIGURE_DEPENDS "${CMAKE_SOURCE_DIR}/addon/*.py" "${CMAKE_SOURCE_DIR}/addon/core/*.py")
  add_custom_target(addon_zip
    COMMAND "${CMAKE_COMMAND}"
      "-DSOURCE_DIR=${CMAKE_SOURCE_DIR}"
      "-DSTAGE_DIR=${CMAKE_BINARY_DIR}/addon_stage"
      "-DDIST_DIR=${CMAKE_BINARY_DIR}/dist"
      "-DLIBRARY=$<TARGET_FILE:developable_engine>"
      "-DVERSION=${PROJECT_VERSION}"
      -P "${CMAKE_CURRENT_LIST_FILE}"
    DEPENDS developable_engine ${_ADDON_PY} "${CMAKE_SOURCE_DIR}/blender_manifest.toml"
    COMMENT "Packaging the Blender add-on into ${CMAKE_BINARY_DIR}/dist"
    VERBATIM)
endif()
