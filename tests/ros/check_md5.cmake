# SPDX-License-Identifier: LGPL-2.1-only
# ros.message_md5: type and MD5 of nns_ros_bridge/Tensors as genpy generated them, as computed
# from std_msgs/UInt8MultiArray (ros_peer.py md5), as gencpp generated them, and as
# src/ros/ros_tensors.h states them: all must be nns_ros_bridge/Tensors c55fd4e2c1bd4bdb0a730e17956ba23c.
set(ENV{PYTHONPATH} ${PYTHONPATH})
execute_process(COMMAND /usr/bin/python3 ${PEER} md5 OUTPUT_VARIABLE out RESULT_VARIABLE rc
                OUTPUT_STRIP_TRAILING_WHITESPACE)
set(want "c55fd4e2c1bd4bdb0a730e17956ba23c")
if(NOT rc EQUAL 0 OR NOT out STREQUAL "nns_ros_bridge/Tensors ${want} ${want}")
  message(FATAL_ERROR "python: '${out}' (exit ${rc}), expected 'nns_ros_bridge/Tensors ${want} ${want}'")
endif()
file(READ ${HEADER} hdr)
if(NOT hdr MATCHES "return \"${want}\";" OR NOT hdr MATCHES "return \"nns_ros_bridge/Tensors\";")
  message(FATAL_ERROR "${HEADER} does not carry MD5 ${want} and type nns_ros_bridge/Tensors")
endif()
file(READ ${CMAKE_CURRENT_LIST_DIR}/../../src/ros/ros_tensors.h src)
if(NOT src MATCHES "kMessageMd5 = \"${want}\"")
  message(FATAL_ERROR "src/ros/ros_tensors.h: kMessageMd5 is not ${want}")
endif()
message(STATUS "nns_ros_bridge/Tensors ${want}: python, computed, C++ header and source agree")
