# SPDX-License-Identifier: LGPL-2.1-only
# tensor_ros_src / tensor_ros_sink (src/ros/): only when the nnstreamer_ros module is built.
# Fixture ros_master: a real rosmaster on 127.0.0.1 with a free port, started before the ROS
# tests and stopped by its PID after them (tests/ros/ros_master.py; state in build/ros-test/).
if(TARGET nnstreamer_ros)
  set(_ros_dir ${CMAKE_BINARY_DIR}/ros-test)
  add_test(NAME ros.master_start
           COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/ros/ros_master.py start ${_ros_dir})
  add_test(NAME ros.master_stop
           COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/ros/ros_master.py stop ${_ros_dir})
  set_tests_properties(ros.master_start PROPERTIES FIXTURES_SETUP ros_master LABELS ros TIMEOUT 30)
  set_tests_properties(ros.master_stop PROPERTIES FIXTURES_CLEANUP ros_master LABELS ros TIMEOUT 30)

  # The generated Python class (ros_peer.py) and the generated C++ header agree with the MD5
  # ROS computes from the definition (std_msgs/UInt8MultiArray's MD5 and the field name).
  add_test(NAME ros.message_md5
           COMMAND ${CMAKE_COMMAND} -DPYTHONPATH=${CMAKE_BINARY_DIR}/ros/python
                   -DPEER=${CMAKE_CURRENT_SOURCE_DIR}/ros/ros_peer.py
                   -DHEADER=${CMAKE_BINARY_DIR}/ros/include/nns_ros_bridge/Tensors.h
                   -P ${CMAKE_CURRENT_SOURCE_DIR}/ros/check_md5.cmake)
  set_tests_properties(ros.message_md5 PROPERTIES LABELS ros TIMEOUT 30)

  # A plain roscpp node (C++17, as ROS 1 message headers need) with the generated header.
  add_executable(ros_cpp_peer ros/ros_cpp_peer.cc)
  add_dependencies(ros_cpp_peer nns_ros_messages)
  set_target_properties(ros_cpp_peer PROPERTIES CXX_STANDARD 17)
  target_include_directories(ros_cpp_peer PRIVATE ${CMAKE_BINARY_DIR}/ros/include)
  target_link_libraries(ros_cpp_peer PRIVATE PkgConfig::ROSCPP nns_warnings)

  add_executable(tensor_ros_cases ros/tensor_ros_cases.cc)
  target_link_libraries(tensor_ros_cases PRIVATE nns_test_support nns_warnings)
  target_compile_definitions(tensor_ros_cases PRIVATE NNS_ROS_CPP_PEER="$<TARGET_FILE:ros_cpp_peer>")
  add_dependencies(tensor_ros_cases nnstreamer_ros ros_cpp_peer)
  gtest_discover_tests(tensor_ros_cases DISCOVERY_TIMEOUT 60
    PROPERTIES LABELS ros TIMEOUT 60 FIXTURES_REQUIRED ros_master ENVIRONMENT "GST_PLUGIN_PATH=")
endif()
