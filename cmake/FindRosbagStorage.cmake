# ROS 1's bag storage as Debian 12 packages it (librosbag-storage-dev), without the ROS build
# system: its CMake package wants ament's Python and leaves out the libraries its headers need
# (rostime, roscpp_serialization, cpp_common), and rosbag/bag.h includes pluginlib, whose
# headers Debian puts one folder deeper (/usr/include/pluginlib/pluginlib/...). This defines the
# imported target rosbag::storage.
#
#   find_package(RosbagStorage REQUIRED)

find_path(RosbagStorage_INCLUDE_DIR rosbag/bag.h)
set(RosbagStorage_FOUND TRUE)
set(_rosbag_include_dirs ${RosbagStorage_INCLUDE_DIR})
foreach(nested IN ITEMS pluginlib class_loader ament_index_cpp rcutils rcpputils)
  if(EXISTS ${RosbagStorage_INCLUDE_DIR}/${nested}/${nested})
    list(APPEND _rosbag_include_dirs ${RosbagStorage_INCLUDE_DIR}/${nested})
  endif()
endforeach()
set(_rosbag_libraries)
foreach(lib IN ITEMS rosbag_storage roscpp_serialization rostime cpp_common console_bridge class_loader
                     ament_index_cpp rcutils rcpputils)
  find_library(RosbagStorage_${lib}_LIBRARY NAMES ${lib})
  if(NOT RosbagStorage_${lib}_LIBRARY)
    set(RosbagStorage_FOUND FALSE)
    set(_rosbag_missing ${lib})
  endif()
  list(APPEND _rosbag_libraries ${RosbagStorage_${lib}_LIBRARY})
endforeach()
if(NOT RosbagStorage_INCLUDE_DIR)
  set(RosbagStorage_FOUND FALSE)
  set(_rosbag_missing "rosbag/bag.h")
endif()
if(RosbagStorage_FOUND)
  if(NOT TARGET rosbag::storage)
    add_library(rosbag::storage INTERFACE IMPORTED)
    set_target_properties(rosbag::storage PROPERTIES
      INTERFACE_INCLUDE_DIRECTORIES "${_rosbag_include_dirs}"
      INTERFACE_LINK_LIBRARIES "${_rosbag_libraries}")
  endif()
elseif(RosbagStorage_FIND_REQUIRED)
  message(FATAL_ERROR "ROS 1 bag storage not found (${_rosbag_missing}): install librosbag-storage-dev "
                      "(scripts/setup.sh does)")
endif()
