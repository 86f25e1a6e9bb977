# SPDX-License-Identifier: LGPL-2.1-only
# Tests of tensor_decoder mode=bounding_boxes that call the schemes directly link nns_bbox
# (backends/decoder/bounding_boxes): every tests/decoders/bbox_*_test.cc.
file(GLOB NNS_BBOX_TESTS CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/decoders/bbox_*_test.cc)
foreach(t ${NNS_BBOX_TESTS})
  get_filename_component(name ${t} NAME_WE)
  target_link_libraries(${name} PRIVATE nns_bbox)
endforeach()
