# SPDX-License-Identifier: LGPL-2.1-only
# trainer_bench needs the pytorch trainer sub-plugin (it dlopens it for the direct loop) and
# exports its symbols: the sub-plugin's nnstreamer_trainer_notify_event() resolves to the
# statically registered plugin in this executable.
if(TARGET nns_trainer_pytorch)
  add_dependencies(${name} nns_trainer_pytorch)
  set_target_properties(${name} PROPERTIES ENABLE_EXPORTS ON)
  target_link_libraries(${name} PRIVATE ${CMAKE_DL_LIBS})
else()
  message(STATUS "bench: ${name} not built by default (needs the pytorch trainer)")
  set_target_properties(${name} PROPERTIES EXCLUDE_FROM_ALL TRUE)
endif()
