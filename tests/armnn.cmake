# SPDX-License-Identifier: LGPL-2.1-only
# armnn back-end tests need the sub-plugin built first. tests/slow/ holds the one real
# MobileNet inference on CpuRef (seconds): ctest label "slow", excluded with `ctest -LE slow`.
if(TARGET nns_filter_armnn)
  foreach(t armnn_backend_test armnn_threads_test armnn_filter_test armnn_mobilenet_test)
    if(TARGET ${t})
      add_dependencies(${t} nns_filter_armnn)
    endif()
  endforeach()
endif()
