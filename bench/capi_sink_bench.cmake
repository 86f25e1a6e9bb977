# SPDX-License-Identifier: LGPL-2.1-only
# Uses the Pipeline API library and the plugin module (not the statically registered elements).
target_link_libraries(${name} PRIVATE capi-nnstreamer)
add_dependencies(${name} nnstreamer)
