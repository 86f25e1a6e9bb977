# SPDX-License-Identifier: LGPL-2.1-only
# mqttsink/mqttsrc are their own plugin (libgstmqtt.so): the MQTT test links its objects and
# registers it statically (nns_mqtt_register_static in the test's environment).
if(TARGET mqtt_elements_test)
  target_link_libraries(mqtt_elements_test PRIVATE nns_gst_mqtt)
endif()
