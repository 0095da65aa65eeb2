# Loaded into every CMake project of the ROS 2 workspace through CMAKE_PROJECT_INCLUDE (scripts/ros2-env).
#
# The ROS 2 wheels on PyPI are built in a manylinux container, and their exported CMake targets
# (<pkg>::<pkg>__rosidl_generator_py) keep that container's Python and NumPy include directories,
# /opt/python/cp311-cp311/include/python3.11 and .../site-packages/numpy/_core/include, which do not exist
# here: CMake refuses to generate ("Imported target ... includes non-existent path"). At the end of the
# configure step, every imported target's include directories are pointed at this Python's and NumPy's.
cmake_language(DEFER DIRECTORY "${CMAKE_SOURCE_DIR}" CALL _ros2_wheels_fix_python_includes)

function(_ros2_wheels_fix_python_includes)
  find_package(Python3 QUIET COMPONENTS Interpreter Development.Module NumPy)
  get_directory_property(targets DIRECTORY "${CMAKE_SOURCE_DIR}" IMPORTED_TARGETS)
  foreach(target IN LISTS targets)
    get_target_property(dirs ${target} INTERFACE_INCLUDE_DIRECTORIES)
    if(NOT dirs OR NOT dirs MATCHES "/opt/python/")
      continue()
    endif()
    set(fixed "")
    foreach(dir IN LISTS dirs)
      if(dir MATCHES "^/opt/python/.*/numpy/")
        list(APPEND fixed ${Python3_NumPy_INCLUDE_DIRS})
      elseif(dir MATCHES "^/opt/python/.*/include/python")
        list(APPEND fixed ${Python3_INCLUDE_DIRS})
      else()
        list(APPEND fixed "${dir}")
      endif()
    endforeach()
    list(REMOVE_DUPLICATES fixed)
    set_target_properties(${target} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${fixed}")
  endforeach()
endfunction()
