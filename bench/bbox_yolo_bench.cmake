# SPDX-License-Identifier: LGPL-2.1-only
# bbox_yolo_bench calls the YOLO schemes of nns_bbox (backends/decoder/bounding_boxes) directly.
if(TARGET nns_bbox)
  target_link_libraries(${name} PRIVATE nns_bbox)
else()
  set_target_properties(${name} PROPERTIES EXCLUDE_FROM_ALL TRUE)
endif()
