/* SPDX-License-Identifier: LGPL-2.1-only */
/* Uses nnstreamer_plugin_api.h (exported by libnnstreamer.so, the plugin) from a program built
 * against the installed headers: config -> caps -> config round trip, a 20-tensor buffer, and
 * nnstreamer_plugin_api_filter.h's accelerator helpers (parse_accl_hw() as sub-plugins call it)
 * and nnstreamer_internal.h's framework detection.
 * Prints what it got; exits 1 on the first mismatch. */
#include <stdio.h>
#include <string.h>

#include <nnstreamer_plugin_api.h>
#include <nnstreamer_internal.h>
#include <nnstreamer_plugin_api_filter.h>

static int fail(const char *what, const char *got) {
  printf("MISMATCH %s: %s\n", what, got ? got : "(null)");
  return 1;
}

int main(void) {
  GstTensorsConfig c, back;
  GstCaps *caps;
  gchar *s;
  GstBuffer *buf;
  guint i;
  int rc = 0;
  gst_init(NULL, NULL);
  gst_tensors_config_init(&c);
  c.info.num_tensors = 2;
  gst_tensors_info_parse_dimensions_string(&c.info, "3:4:1:1,2");
  gst_tensors_info_parse_types_string(&c.info, "uint8,float32");
  c.rate_n = 30;
  c.rate_d = 1;
  caps = gst_tensors_caps_from_config(&c);
  s = gst_caps_to_string(caps);
  printf("%s\n", s);
  if (strcmp(s,
             "other/tensors, format=(string)static, num_tensors=(int)2, "
             "framerate=(fraction)30/1, dimensions=(string)\"3:4:1:1\\,2\", "
             "types=(string)\"uint8\\,float32\"") != 0)
    rc |= fail("caps", s);
  g_free(s);
  if (!gst_tensors_config_from_caps(&back, caps, TRUE) || !gst_tensors_config_is_equal(&c, &back))
    rc |= fail("round trip", "not equal");
  gst_caps_unref(caps);
  gst_tensors_config_free(&back);

  /* 20 tensors of i+1 bytes: the last 5 are packed into the 16th memory. */
  buf = gst_buffer_new();
  for (i = 0; i < 20; ++i) {
    GstTensorInfo info;
    GstMemory *mem = gst_allocator_alloc(NULL, i + 1, NULL);
    GstMapInfo fill;
    if (gst_memory_map(mem, &fill, GST_MAP_WRITE)) {
      memset(fill.data, (int)i, fill.size);
      gst_memory_unmap(mem, &fill);
    }
    gst_tensor_info_init(&info);
    info.type = _NNS_UINT8;
    info.dimension[0] = i + 1;
    if (!gst_tensor_buffer_append_memory(buf, mem, &info)) rc |= fail("append", "FALSE");
  }
  printf("tensors %u memories %u\n", gst_tensor_buffer_get_count(buf), gst_buffer_n_memory(buf));
  if (gst_tensor_buffer_get_count(buf) != 20 || gst_buffer_n_memory(buf) != 16)
    rc |= fail("count", "not 20 tensors in 16 memories");
  for (i = 0; i < 20; ++i) {
    GstMemory *m = gst_tensor_buffer_get_nth_memory(buf, i);
    GstMapInfo map;
    if (!m || !gst_memory_map(m, &map, GST_MAP_READ) || map.size != i + 1 ||
        map.data[0] != (guint8)i || map.data[i] != (guint8)i) {
      rc |= fail("nth memory", "wrong bytes");
    } else {
      gst_memory_unmap(m, &map);
    }
    if (m) gst_memory_unref(m);
  }
  gst_buffer_unref(buf);
  gst_tensors_config_free(&c);

  {
    const char *sup[] = {ACCL_NPU_STR, ACCL_GPU_STR, ACCL_CPU_STR, NULL};
    parse_accl_args args = {.in_accl = "true:!npu,cpu,gpu", .sup_accl = sup};
    printf("accl %s %d %s\n", get_accl_hw_str(get_accl_hw_type("npu.edgetpu")),
           (int)parse_accl_hw_fill(args),
           get_accl_hw_str(parse_accl_hw("true", sup, "gpu", "cpu")));
    if (get_accl_hw_type("npu.edgetpu") != ACCL_NPU_EDGE_TPU)
      rc |= fail("accl type", "npu.edgetpu");
    if (parse_accl_hw_fill(args) != ACCL_CPU) rc |= fail("parse_accl_hw", "true:!npu,cpu,gpu");
    if (parse_accl_hw("true", sup, "gpu", "cpu") != ACCL_GPU) rc |= fail("parse_accl_hw", "true");
    if (parse_accl_hw(NULL, sup, "gpu", "cpu") != ACCL_CPU) rc |= fail("parse_accl_hw", "NULL");
  }
  {
    const gchar *models[] = {"model.tflite"};
    gchar *fw = gst_tensor_filter_detect_framework(models, 1, FALSE);
    printf("detected %s\n", fw ? fw : "(null)");
    if (!fw || strcmp(fw, "tensorflow-lite") != 0) rc |= fail("detect_framework", fw);
    g_free(fw);
  }
  printf(rc ? "FAILED\n" : "OK\n");
  return rc;
}
