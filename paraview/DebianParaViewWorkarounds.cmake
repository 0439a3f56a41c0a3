# Debian 12's paraview-dev (ParaView 5.11) beside python3-vtk9, without python3-paraview.
#
# ParaView's CMake package lists imported targets for its Python modules (VTKPython-targets.cmake,
# ParaViewPython-targets.cmake) and for pvpython (ParaViewTools-targets.cmake), whose files only
# python3-paraview ships (/usr/lib/python3/dist-packages/vtkmodules/*.so, paraview/modules/*.so,
# /usr/bin/pvpython); python3-paraview conflicts with python3-vtk9, which BaryLab's Python package
# needs. CMake's generated target files stop the configure with "The imported target ...
# references the file ... but this file does not exist". Those files return early, before that
# check, when every target they define exists already: so the targets of those three files are
# defined here first, as empty INTERFACE IMPORTED targets. The plugin uses none of them (no
# Python in the plugin). Nothing is defined when the files that python3-paraview ships are
# present (a ParaView with its Python installed needs no workaround).
#
# Used by paraview/CMakeLists.txt before find_package(ParaView); see docs/paraview.md.
function(barylab_paraview_placeholder_targets paraview_cmake_dir)
  if(EXISTS /usr/bin/pvpython)
    return()
  endif()
  set(_count 0)
  foreach(_file vtk/VTKPython-targets.cmake ParaViewPython-targets.cmake
      ParaViewTools-targets.cmake)
    set(_path "${paraview_cmake_dir}/${_file}")
    if(NOT EXISTS "${_path}")
      continue()
    endif()
    file(STRINGS "${_path}" _line REGEX "^foreach\\(_cmake_expected_target IN ITEMS ")
    string(REGEX REPLACE "^foreach\\(_cmake_expected_target IN ITEMS (.*)\\)$" "\\1" _line
      "${_line}")
    separate_arguments(_targets UNIX_COMMAND "${_line}")
    foreach(_target IN LISTS _targets)
      if(NOT TARGET ${_target})
        add_library(${_target} INTERFACE IMPORTED)
        math(EXPR _count "${_count} + 1")
      endif()
    endforeach()
  endforeach()
  message(STATUS "BaryLab ParaView plugin: ${_count} placeholder targets for ParaView's "
    "Python modules and pvpython (python3-paraview is not installed; docs/paraview.md)")
endfunction()

# Debian's paraview-dev ships no wrap-hierarchy files of ParaView's VTK (the files
# lib/<arch>/vtk/hierarchy/ParaView/vtk*-hierarchy.txt its CMake package names): the client-server
# wrapping of the plugin's modules needs those of every module they depend on (ninja: "...
# vtkCommonCore-hierarchy.txt, needed by ...BaryLabFilters-hierarchy.txt, missing and no known
# rule to make it"). They are made here, at configure time, with ParaView's own
# vtkWrapHierarchy-pv5.11 from the headers each module's CMake properties list (under a second
# per module), for the modules @p modules need (their depends and private depends, closed), and
# the targets are pointed at them.
function(barylab_paraview_wrap_hierarchies)
  set(_pending ${ARGN})
  set(_seen)
  set(_order)
  # depth-first, dependencies first
  while(_pending)
    list(GET _pending 0 _module)
    if(_module IN_LIST _seen OR NOT TARGET ${_module})
      list(REMOVE_AT _pending 0)
      if(NOT _module IN_LIST _seen)
        list(APPEND _seen ${_module})
      endif()
      continue()
    endif()
    get_target_property(_deps ${_module} INTERFACE_vtk_module_depends)
    get_target_property(_private ${_module} INTERFACE_vtk_module_private_depends)
    set(_missing)
    foreach(_dep IN LISTS _deps _private)
      if(_dep AND TARGET ${_dep} AND NOT _dep IN_LIST _seen AND NOT _dep IN_LIST _pending)
        list(APPEND _missing ${_dep})
      endif()
    endforeach()
    if(_missing)
      list(PREPEND _pending ${_missing})
      continue()
    endif()
    list(REMOVE_AT _pending 0)
    list(APPEND _seen ${_module})
    list(APPEND _order ${_module})
  endwhile()

  get_target_property(_configurations VTK::WrapHierarchy IMPORTED_CONFIGURATIONS)
  list(GET _configurations 0 _configuration)
  get_target_property(_tool VTK::WrapHierarchy IMPORTED_LOCATION_${_configuration})
  get_target_property(_includes VTK::CommonCore INTERFACE_INCLUDE_DIRECTORIES)
  list(TRANSFORM _includes PREPEND "-I")
  set(_dir "${CMAKE_BINARY_DIR}/paraview-wrap-hierarchy")
  file(MAKE_DIRECTORY "${_dir}")
  set(_made 0)
  foreach(_module IN LISTS _order)
    get_target_property(_hierarchy ${_module} INTERFACE_vtk_module_hierarchy)
    get_target_property(_headers ${_module} INTERFACE_vtk_module_headers)
    get_target_property(_library ${_module} INTERFACE_vtk_module_library_name)
    if(NOT _hierarchy OR EXISTS "${_hierarchy}" OR NOT _headers OR NOT _library)
      continue()
    endif()
    set(_output "${_dir}/${_library}-hierarchy.txt")
    if(NOT EXISTS "${_output}")
      set(_data "")
      foreach(_header IN LISTS _headers)
        string(APPEND _data "${_header};${_library}\n")
      endforeach()
      file(WRITE "${_dir}/${_library}.data" "${_data}")
      # the hierarchies of its dependencies, made before it
      set(_depends_args "")
      get_target_property(_deps ${_module} INTERFACE_vtk_module_depends)
      foreach(_dep IN LISTS _deps)
        if(_dep AND TARGET ${_dep})
          get_target_property(_dep_hierarchy ${_dep} INTERFACE_vtk_module_hierarchy)
          if(_dep_hierarchy AND EXISTS "${_dep_hierarchy}")
            string(APPEND _depends_args "\"${_dep_hierarchy}\"\n")
          endif()
        endif()
      endforeach()
      file(WRITE "${_dir}/${_library}.depends.args" "${_depends_args}")
      execute_process(
        COMMAND "${_tool}" ${_includes} -o "${_output}" "${_dir}/${_library}.data" "@${_dir}/${_library}.depends.args"
        RESULT_VARIABLE _result ERROR_VARIABLE _error)
      if(NOT _result EQUAL 0)
        message(FATAL_ERROR "vtkWrapHierarchy failed for ${_module}: ${_error}")
      endif()
    endif()
    set_property(TARGET ${_module} PROPERTY INTERFACE_vtk_module_hierarchy "${_output}")
    math(EXPR _made "${_made} + 1")
  endforeach()
  message(STATUS "BaryLab ParaView plugin: ${_made} wrap-hierarchy files of ParaView's VTK made "
    "(Debian ships none; docs/paraview.md)")
endfunction()
