# Debian splits OpenCV into per-module -dev packages that ship headers and libraries but no CMake
# package file (that comes only with the all-modules libopencv-dev). This finds the modules we use
# and defines imported targets opencv::<module>.
#
#   find_package(OpenCVModules REQUIRED COMPONENTS core imgproc imgcodecs)

find_path(OpenCVModules_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4)
find_path(OpenCVModules_ARCH_INCLUDE_DIR opencv2/cvconfig.h PATH_SUFFIXES x86_64-linux-gnu/opencv4 opencv4)
set(OpenCVModules_FOUND TRUE)
foreach(module IN LISTS OpenCVModules_FIND_COMPONENTS)
  find_library(OpenCVModules_${module}_LIBRARY NAMES opencv_${module})
  if(OpenCVModules_${module}_LIBRARY AND OpenCVModules_INCLUDE_DIR)
    if(NOT TARGET opencv::${module})
      add_library(opencv::${module} UNKNOWN IMPORTED)
      set_target_properties(opencv::${module} PROPERTIES
        IMPORTED_LOCATION "${OpenCVModules_${module}_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${OpenCVModules_INCLUDE_DIR}")
      if(OpenCVModules_ARCH_INCLUDE_DIR)
        set_property(TARGET opencv::${module} APPEND PROPERTY
          INTERFACE_INCLUDE_DIRECTORIES "${OpenCVModules_ARCH_INCLUDE_DIR}")
      endif()
    endif()
  else()
    set(OpenCVModules_FOUND FALSE)
    if(OpenCVModules_FIND_REQUIRED)
      message(FATAL_ERROR "OpenCV module '${module}' not found: install libopencv-${module}-dev")
    endif()
  endif()
endforeach()
