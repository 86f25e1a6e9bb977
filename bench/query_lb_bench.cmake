# SPDX-License-Identifier: LGPL-2.1-only
# query_lb_bench drives its clients with appsrc (gstreamer-app-1.0).
pkg_check_modules(NNS_GSTAPP_LB REQUIRED IMPORTED_TARGET gstreamer-app-1.0)
target_link_libraries(${name} PRIVATE PkgConfig::NNS_GSTAPP_LB)
