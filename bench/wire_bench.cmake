# SPDX-License-Identifier: LGPL-2.1-only
# wire_bench links the wire-format library (backends/common/wire); without it it is not built.
if(TARGET nns_wire)
  target_link_libraries(${name} PRIVATE nns_wire)
  target_compile_definitions(${name} PRIVATE NNS_HAVE_WIRE=1)
else()
  set_target_properties(${name} PROPERTIES EXCLUDE_FROM_ALL TRUE)
endif()
