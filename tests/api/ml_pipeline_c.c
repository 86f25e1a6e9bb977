/* SPDX-License-Identifier: LGPL-2.1-only */
/* The Pipeline API from plain C (nnstreamer.h compiled as C): a custom-easy filter
 * (int16[3] -> int16[3], out = -in) between appsrc and tensor_sink, data pushed with both
 * buffer policies, exact values checked in the sink callback, a valve and an element property.
 * Prints "N passed, N failed" and exits non-zero on failure. */
#define _POSIX_C_SOURCE 200809L
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gst/gst.h>

#include "nnstreamer.h"

static int passed, failed;
#define CHECK(cond)                                                                      \
  do {                                                                                   \
    if (cond) {                                                                          \
      ++passed;                                                                          \
    } else {                                                                             \
      ++failed;                                                                          \
      fprintf(stderr, "%s:%d: %s failed (%s)\n", __FILE__, __LINE__, #cond, ml_error()); \
    }                                                                                    \
  } while (0)

static volatile int received;
static int16_t last[3];

static int negate(const ml_tensors_data_h in, ml_tensors_data_h out, void *user) {
  void *ip, *op;
  size_t is, os, i;
  (void)user;
  if (ml_tensors_data_get_tensor_data(in, 0, &ip, &is) ||
      ml_tensors_data_get_tensor_data(out, 0, &op, &os))
    return -1;
  for (i = 0; i < is / 2; ++i) ((int16_t *)op)[i] = (int16_t) - ((int16_t *)ip)[i];
  return 0;
}

static void on_data(const ml_tensors_data_h data, const ml_tensors_info_h info, void *user) {
  void *raw;
  size_t size;
  unsigned int n = 0;
  (void)user;
  ml_tensors_info_get_count(info, &n);
  if (n == 1 && ml_tensors_data_get_tensor_data(data, 0, &raw, &size) == ML_ERROR_NONE &&
      size == 6) {
    memcpy(last, raw, 6);
    __atomic_add_fetch(&received, 1, __ATOMIC_SEQ_CST);
  }
}

static int wait_received(int n) {
  int i;
  struct timespec ts = {0, 5000000L};
  for (i = 0; i < 2000; ++i) {
    if (__atomic_load_n(&received, __ATOMIC_SEQ_CST) >= n) return 1;
    nanosleep(&ts, NULL);
  }
  return 0;
}

static int thread_count(void) {
  char line[256];
  int n = -1;
  FILE *f = fopen("/proc/self/status", "r");
  if (!f) return -1;
  while (fgets(line, sizeof line, f))
    if (strncmp(line, "Threads:", 8) == 0) n = atoi(line + 8);
  fclose(f);
  return n;
}

/* As tests/api/ml_pipeline_main.cc: end GStreamer and wait for GLib's idle pool threads. */
static void end_gstreamer(void) {
  int i;
  gst_deinit();
  g_thread_pool_set_max_unused_threads(0);
  for (i = 0; i < 300 && thread_count() > 1; ++i) {
    g_thread_pool_stop_unused_threads();
    g_usleep(10000);
  }
}

int main(void) {
  const char *b = NNS_BUILD_DIR;
  char path[4096];
  ml_tensors_info_h info;
  ml_tensor_dimension dim = {3, 1, 1, 1};
  ml_custom_easy_filter_h custom;
  ml_pipeline_h pipe;
  ml_pipeline_src_h src;
  ml_pipeline_sink_h sink;
  ml_pipeline_valve_h valve;
  ml_pipeline_element_h elem;
  ml_tensors_data_h data;
  int16_t v[3] = {1, -2, 300};
  int32_t drop = -1;

  /* ctest sets the GStreamer environment (tests/api_pipeline.cmake); by hand: this tree. */
  snprintf(path, sizeof path, "%s/plugin", b);
  setenv("GST_PLUGIN_PATH", path, 0);

  CHECK(ml_tensors_info_create(&info) == ML_ERROR_NONE);
  CHECK(ml_tensors_info_set_count(info, 1) == ML_ERROR_NONE);
  CHECK(ml_tensors_info_set_tensor_type(info, 0, ML_TENSOR_TYPE_INT16) == ML_ERROR_NONE);
  CHECK(ml_tensors_info_set_tensor_dimension(info, 0, dim) == ML_ERROR_NONE);
  CHECK(ml_pipeline_custom_easy_filter_register("c_negate", info, info, negate, NULL, &custom) ==
        ML_ERROR_NONE);
  CHECK(ml_pipeline_construct(
            "appsrc name=src caps=other/tensors,format=static,num_tensors=1,dimensions=3:1:1:1,"
            "types=int16,framerate=0/1 ! valve name=v ! tensor_filter framework=custom-easy "
            "model=c_negate ! tensor_sink name=sink async=false",
            NULL, NULL, &pipe) == ML_ERROR_NONE);
  CHECK(ml_pipeline_src_get_handle(pipe, "src", &src) == ML_ERROR_NONE);
  CHECK(ml_pipeline_sink_register(pipe, "sink", on_data, NULL, &sink) == ML_ERROR_NONE);
  CHECK(ml_pipeline_valve_get_handle(pipe, "v", &valve) == ML_ERROR_NONE);
  CHECK(ml_pipeline_element_get_handle(pipe, "v", &elem) == ML_ERROR_NONE);
  CHECK(ml_pipeline_start(pipe) == ML_ERROR_NONE);

  CHECK(ml_tensors_data_create(info, &data) == ML_ERROR_NONE);
  CHECK(ml_tensors_data_set_tensor_data(data, 0, v, sizeof v) == ML_ERROR_NONE);
  CHECK(ml_pipeline_src_input_data(src, data, ML_PIPELINE_BUF_POLICY_DO_NOT_FREE) == ML_ERROR_NONE);
  CHECK(wait_received(1));
  CHECK(last[0] == -1 && last[1] == 2 && last[2] == -300);

  CHECK(ml_pipeline_valve_set_open(valve, false) == ML_ERROR_NONE);
  CHECK(ml_pipeline_element_get_property_bool(elem, "drop", &drop) == ML_ERROR_NONE);
  CHECK(drop == 1);
  CHECK(ml_pipeline_valve_set_open(valve, true) == ML_ERROR_NONE);
  v[0] = 7;
  CHECK(ml_tensors_data_set_tensor_data(data, 0, v, sizeof v) == ML_ERROR_NONE);
  CHECK(ml_pipeline_src_input_data(src, data, ML_PIPELINE_BUF_POLICY_AUTO_FREE) == ML_ERROR_NONE);
  CHECK(wait_received(2));
  CHECK(last[0] == -7);

  CHECK(ml_pipeline_element_release_handle(elem) == ML_ERROR_NONE);
  CHECK(ml_pipeline_valve_release_handle(valve) == ML_ERROR_NONE);
  CHECK(ml_pipeline_sink_unregister(sink) == ML_ERROR_NONE);
  CHECK(ml_pipeline_src_release_handle(src) == ML_ERROR_NONE);
  CHECK(ml_pipeline_destroy(pipe) == ML_ERROR_NONE);
  CHECK(ml_pipeline_custom_easy_filter_unregister(custom) == ML_ERROR_NONE);
  CHECK(ml_tensors_info_destroy(info) == ML_ERROR_NONE);
  end_gstreamer();
  printf("%d passed, %d failed\n", passed, failed);
  return failed ? 1 : 0;
}
