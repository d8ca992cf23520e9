# orcs_check_layering(): docs/architecture.md's one dependency rule, checked at configure time for every top folder.
#
# Each top folder may use itself and the folders listed for it below, nothing else of the project; some may not
# use certain outside libraries at all (a broker runs on a head node with no physics; the model knows no wire).
# Two checks per folder, both failing the configuration with one line that names the culprit:
#   - links: every target defined under the folder, with everything it links directly or through others;
#   - includes: every "#include" of the folder's .h/.cc files (quoted project paths and the forbidden libraries'
#     headers), so that a header-only use cannot slip past the link check.
# tests/ and scripts/ are outside the rule: tests may use whatever they check.

# folder → the other project folders it may use.
# base/ (the always-on invariant check) is what every layer shares; it uses nothing of the project.
set(_ORCS_LAYER_USES_base    "")
set(_ORCS_LAYER_USES_proto   "base")
set(_ORCS_LAYER_USES_model   "base")
set(_ORCS_LAYER_USES_net     "base;proto")
set(_ORCS_LAYER_USES_broker  "base;net;proto")
set(_ORCS_LAYER_USES_worker  "base;model;net;proto")
set(_ORCS_LAYER_USES_viewer  "base;model;net;proto;worker")  # worker/osp: the OSP-driven live mode (orcs-osp -gui)
set(_ORCS_LAYER_USES_clients "base;model;net;proto;broker")
# the servo bus: codecs and drivers, no wire; worker/osp's ODCP server fronts the robot for motion editors
set(_ORCS_LAYER_USES_hardware "base;model;worker")
set(_ORCS_LAYER_FOLDERS base proto model net broker worker viewer clients hardware)

# folder → outside libraries it may not use: a regex over link items, one over included headers.
set(_ORCS_LAYER_PHYSICS_LINKS "^(PkgConfig::ODE|ODE::.*|.*libode.*|.*mujoco.*)$")
set(_ORCS_LAYER_PHYSICS_HEADERS "^(ode|mujoco)/")
set(_ORCS_LAYER_WIRE_LINKS "(zmq|protobuf)")
set(_ORCS_LAYER_WIRE_HEADERS "^(zmq\\.h|zmq\\.hpp|zmq_addon\\.hpp|google/protobuf/|orcs/v1/)")
foreach(folder proto net broker)
  set(_ORCS_LAYER_FORBIDDEN_LINKS_${folder} "${_ORCS_LAYER_PHYSICS_LINKS}")
  set(_ORCS_LAYER_FORBIDDEN_HEADERS_${folder} "${_ORCS_LAYER_PHYSICS_HEADERS}")
endforeach()
foreach(folder base)  # the standard library only: neither physics nor the wire
  set(_ORCS_LAYER_FORBIDDEN_LINKS_${folder} "${_ORCS_LAYER_PHYSICS_LINKS}|${_ORCS_LAYER_WIRE_LINKS}")
  set(_ORCS_LAYER_FORBIDDEN_HEADERS_${folder} "${_ORCS_LAYER_PHYSICS_HEADERS}|${_ORCS_LAYER_WIRE_HEADERS}")
endforeach()
foreach(folder model hardware)
  set(_ORCS_LAYER_FORBIDDEN_LINKS_${folder} "${_ORCS_LAYER_WIRE_LINKS}")
  set(_ORCS_LAYER_FORBIDDEN_HEADERS_${folder} "${_ORCS_LAYER_WIRE_HEADERS}")
endforeach()

# The top folder (proto, model, ...) a path inside the project lies in; "" for the project's root or outside it.
function(_orcs_top_folder path out_var)
  file(RELATIVE_PATH rel "${PROJECT_SOURCE_DIR}" "${path}")
  string(REGEX MATCH "^[^/]+" top "${rel}")
  if(rel STREQUAL "" OR top STREQUAL ".." OR NOT top IN_LIST _ORCS_LAYER_FOLDERS)
    set(top "")
  endif()
  set(${out_var} "${top}" PARENT_SCOPE)
endfunction()

# Every buildsystem target defined in `dir` and its subdirectories.
function(_orcs_targets_under dir out_var)
  get_property(targets DIRECTORY "${dir}" PROPERTY BUILDSYSTEM_TARGETS)
  get_property(subdirs DIRECTORY "${dir}" PROPERTY SUBDIRECTORIES)
  foreach(sub IN LISTS subdirs)
    _orcs_targets_under("${sub}" more)
    list(APPEND targets ${more})
  endforeach()
  set(${out_var} ${targets} PARENT_SCOPE)
endfunction()

function(_orcs_check_folder_links folder)
  set(allowed ${folder} ${_ORCS_LAYER_USES_${folder}})
  set(forbidden "${_ORCS_LAYER_FORBIDDEN_LINKS_${folder}}")
  _orcs_targets_under("${PROJECT_SOURCE_DIR}/${folder}" targets)
  foreach(target IN LISTS targets)
    set(found "")
    _orcs_collect_links(${target} found)
    list(REMOVE_ITEM found ${target})
    foreach(item IN LISTS found)
      if(TARGET "${item}")
        get_target_property(imported "${item}" IMPORTED)
        if(NOT imported)
          get_target_property(dir "${item}" SOURCE_DIR)
          _orcs_top_folder("${dir}" top)
          if(NOT top STREQUAL "" AND NOT top IN_LIST allowed)
            message(FATAL_ERROR "orcs layering: ${target} (${folder}/) links ${item} from ${top}/; docs/architecture.md lets "
                                "${folder}/ use only: ${allowed}")
          endif()
          continue()
        endif()
      endif()
      if(NOT forbidden STREQUAL "" AND item MATCHES "${forbidden}")
        message(FATAL_ERROR "orcs layering: ${target} (${folder}/) links ${item}, which ${folder}/ may not use "
                            "(docs/architecture.md's dependency rule)")
      endif()
    endforeach()
  endforeach()
endfunction()

function(_orcs_check_folder_includes folder)
  set(allowed ${folder} ${_ORCS_LAYER_USES_${folder}})
  set(forbidden "${_ORCS_LAYER_FORBIDDEN_HEADERS_${folder}}")
  file(GLOB_RECURSE sources "${PROJECT_SOURCE_DIR}/${folder}/*.h" "${PROJECT_SOURCE_DIR}/${folder}/*.cc")
  foreach(source IN LISTS sources)
    file(STRINGS "${source}" includes REGEX "^[ \t]*#[ \t]*include[ \t]*[<\"]")
    foreach(line IN LISTS includes)
      string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*[<\"]([^>\"]*)[>\"].*$" "\\1" header "${line}")
      string(REGEX MATCH "^[^/]+" first "${header}")
      if(first STREQUAL "orcs" AND header MATCHES "^orcs/v1/")
        set(first proto)  # the generated wire messages
      endif()
      file(RELATIVE_PATH shown "${PROJECT_SOURCE_DIR}" "${source}")
      if(first IN_LIST _ORCS_LAYER_FOLDERS AND NOT first IN_LIST allowed)
        message(FATAL_ERROR "orcs layering: ${shown} includes \"${header}\" from ${first}/; docs/architecture.md lets "
                            "${folder}/ use only: ${allowed}")
      endif()
      if(NOT forbidden STREQUAL "" AND header MATCHES "${forbidden}")
        message(FATAL_ERROR "orcs layering: ${shown} includes <${header}>, which ${folder}/ may not use "
                            "(docs/architecture.md's dependency rule)")
      endif()
    endforeach()
  endforeach()
endfunction()

# Inside a top folder: a sub-folder that must not call back into its user (no circles between file pairs). Fails
# the configuration naming the culprit when one of `subfolder`'s files includes a header whose path matches
# `pattern`, or (where the sub-folder defines targets of its own) one of its targets links a project target defined
# in a folder matching it.
# The folder of a target's first source file, relative to the project (clients/CMakeLists.txt defines orcs_batch
# from batch/*.cc: its folder is clients/batch).
function(_orcs_target_folder target out_var)
  get_target_property(dir ${target} SOURCE_DIR)
  get_target_property(sources ${target} SOURCES)
  if(sources)
    list(GET sources 0 first)
    if(NOT IS_ABSOLUTE "${first}")
      set(first "${dir}/${first}")
    endif()
    get_filename_component(dir "${first}" DIRECTORY)
  endif()
  file(RELATIVE_PATH rel "${PROJECT_SOURCE_DIR}" "${dir}")
  set(${out_var} "${rel}" PARENT_SCOPE)
endfunction()

function(_orcs_forbid_uses subfolder pattern why)
  file(GLOB_RECURSE sources "${PROJECT_SOURCE_DIR}/${subfolder}/*.h" "${PROJECT_SOURCE_DIR}/${subfolder}/*.cc")
  foreach(source IN LISTS sources)
    file(STRINGS "${source}" includes REGEX "^[ \t]*#[ \t]*include[ \t]*\"")
    foreach(line IN LISTS includes)
      string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*\"([^\"]*)\".*$" "\\1" header "${line}")
      if(header MATCHES "${pattern}")
        file(RELATIVE_PATH shown "${PROJECT_SOURCE_DIR}" "${source}")
        message(FATAL_ERROR "orcs layering: ${shown} includes \"${header}\": ${why}")
      endif()
    endforeach()
  endforeach()
  if(NOT EXISTS "${PROJECT_SOURCE_DIR}/${subfolder}/CMakeLists.txt")
    return()
  endif()
  _orcs_targets_under("${PROJECT_SOURCE_DIR}/${subfolder}" targets)
  foreach(target IN LISTS targets)
    set(found "")
    _orcs_collect_links(${target} found)
    foreach(item IN LISTS found)
      if(TARGET "${item}")
        get_target_property(imported "${item}" IMPORTED)
        if(NOT imported)
          _orcs_target_folder(${item} rel)
          if("${rel}/" MATCHES "${pattern}")
            message(FATAL_ERROR "orcs layering: ${target} (${subfolder}/) links ${item} from ${rel}/: ${why}")
          endif()
        endif()
      endif()
    endforeach()
  endforeach()
endfunction()

function(orcs_check_layering)
  foreach(folder IN LISTS _ORCS_LAYER_FOLDERS)
    _orcs_check_folder_links(${folder})
    _orcs_check_folder_includes(${folder})
  endforeach()
  _orcs_forbid_uses(worker/osp "^worker/(sim|job)/"
                    "orcs-sim uses the OSP/ODCP servers, so worker/osp/ never uses worker/sim/ or worker/job/ (what both need lives in worker/)")
  _orcs_forbid_uses(clients/runtime "^clients/(batch|evolve|gap|regress)/"
                    "the client runtime is what every client program shares, so it never uses a client's own code (docs/architecture.md)")
  _orcs_forbid_uses(clients/gap "^clients/(batch|evolve|regress)/"
                    "orcs-gap is a program of its own on the client runtime (clients/runtime/), not on orcs-batch's commands")
endfunction()
