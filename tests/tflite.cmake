# SPDX-License-Identifier: LGPL-2.1-only
# tflite back-end tests: they build models with the back end's schema (nns_tflite_model carries
# the flatc-generated header) and need the sub-plugin built first.
foreach(t tflite_ops_test tflite_ops_data_test tflite_ops_misc_test tflite_quant_add_test tflite_backend_test
          tflite_reference_test tflite_deeplab_test)
  if(TARGET ${t} AND TARGET nns_tflite_model)
    target_link_libraries(${t} PRIVATE nns_tflite_model)
    if(TARGET nns_filter_tflite)
      add_dependencies(${t} nns_filter_tflite)
    endif()
  endif()
endforeach()
# The exact-arithmetic reference MobileNet v2 quant is checked against.
if(TARGET tflite_backend_test AND TARGET nns_tflite_model)
  target_sources(tflite_backend_test PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/backends/tflite_exact_reference.cc)
endif()
# tflite_reference_test decodes palm boxes (bounding_boxes sub-plugin) and compares
# person_detect with Arm NN CpuRef when that back end is built.
foreach(dep nns_decoder_bounding_boxes nns_filter_armnn)
  if(TARGET tflite_reference_test AND TARGET ${dep})
    add_dependencies(tflite_reference_test ${dep})
  endif()
endforeach()
