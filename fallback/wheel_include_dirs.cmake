# The PyPI wheels' exported CMake targets carry the include directories of the machine that built
# them (/opt/python/cp311-cp311/...). Re-point them at this interpreter's Python and numpy
# include directories (found by rosidl_generator_py), or CMake refuses the non-existent paths.
set(_wheel_python_prefix "/opt/python/cp311-cp311")
get_directory_property(_imported_targets IMPORTED_TARGETS)
foreach(_target IN LISTS _imported_targets)
  get_target_property(_includes ${_target} INTERFACE_INCLUDE_DIRECTORIES)
  if(_includes AND _includes MATCHES "${_wheel_python_prefix}")
    list(FILTER _includes EXCLUDE REGEX "^${_wheel_python_prefix}")
    list(APPEND _includes ${Python3_INCLUDE_DIRS} ${Python3_NumPy_INCLUDE_DIRS})
    list(REMOVE_DUPLICATES _includes)
    set_target_properties(${_target} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_includes}")
  endif()
endforeach()
