# SPDX-License-Identifier: LGPL-2.1-only
# query_bench drives the client with appsrc/appsink (gstreamer-app-1.0).
pkg_check_modules(NNS_GSTAPP REQUIRED IMPORTED_TARGET gstreamer-app-1.0)
target_link_libraries(${name} PRIVATE PkgConfig::NNS_GSTAPP)
