# SPDX-License-Identifier: LGPL-2.1-only
# Wire-format tests link the GStreamer-free nns_wire library (backends/common/wire); without it
# (protobuf/flatbuffers missing) they compile to GTEST_SKIPs.
foreach(t wire_format_test wire_pipeline_test)
  if(TARGET ${t})
    if(TARGET nns_wire)
      target_link_libraries(${t} PRIVATE nns_wire ${CMAKE_DL_LIBS})
      target_compile_definitions(${t} PRIVATE NNS_HAVE_WIRE=1)
      add_dependencies(${t} nns_converter_protobuf nns_converter_flatbuf nns_converter_flexbuf
                       nns_decoder_protobuf nns_decoder_flatbuf nns_decoder_flexbuf)
    endif()
  endif()
endforeach()
