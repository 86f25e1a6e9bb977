# SPDX-License-Identifier: LGPL-2.1-only
# bbox_ssd_bench calls the mobilenet-ssd scheme directly (backends/decoder/bounding_boxes).
target_link_libraries(${name} PRIVATE nns_bbox)
