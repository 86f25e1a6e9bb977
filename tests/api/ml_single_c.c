/* SPDX-License-Identifier: LGPL-2.1-only */
/* The single-shot API from plain C: custom-easy models (open, query, invoke, invoke_fast,
 * time-out, set_input_info, invoke_dynamic, properties with a model reload) and LeNet on
 * PyTorch through ml_single_open_full and ml_single_open_with_option (skipped when the model
 * or the back end is missing). Prints "N passed, N failed" and exits non-zero on failure. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "nnstreamer-single.h"
#include "tensor_filter_custom_easy.h"

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

static void sleep_ms(long ms) {
  struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
  nanosleep(&ts, NULL);
}

static int scale(const GstTensorMemory *in, GstTensorMemory *out, float k) {
  const float *i = (const float *)in[0].data;
  float *o = (float *)out[0].data;
  for (size_t n = 0; n < in[0].size / sizeof(float); ++n) o[n] = k * i[n];
  return 0;
}

static int double_it(void *data, const GstTensorFilterProperties *prop, const GstTensorMemory *in,
                     GstTensorMemory *out) {
  (void)data;
  (void)prop;
  return scale(in, out, 2.0f);
}

static int triple_it(void *data, const GstTensorFilterProperties *prop, const GstTensorMemory *in,
                     GstTensorMemory *out) {
  (void)data;
  (void)prop;
  return scale(in, out, 3.0f);
}

static int slow_double(void *data, const GstTensorFilterProperties *prop, const GstTensorMemory *in,
                       GstTensorMemory *out) {
  sleep_ms(300);
  return double_it(data, prop, in, out);
}

/* Dynamic: one float32 output {2} = {sum of the input, number of elements}. */
static int sum_count(void *data, const GstTensorsInfo *in_info, GstTensorsInfo *out_info,
                     const GstTensorMemory *in, GstTensorMemory *out) {
  const float *v = (const float *)in[0].data;
  size_t n = in[0].size / sizeof(float);
  float *o = malloc(2 * sizeof(float));
  (void)data;
  (void)in_info;
  if (!o) return -ENOMEM;
  o[0] = 0;
  for (size_t k = 0; k < n; ++k) o[0] += v[k];
  o[1] = (float)n;
  out_info->num_tensors = 1;
  out_info->info[0].type = _NNS_FLOAT32;
  out_info->info[0].dimension[0] = 2;
  out[0].data = o;
  out[0].size = 2 * sizeof(float);
  return 0;
}

static ml_tensors_info_h f32_info(unsigned d0, unsigned d1) {
  ml_tensors_info_h info = NULL;
  ml_tensor_dimension dim = {d0, d1};
  ml_tensors_info_create(&info);
  ml_tensors_info_set_count(info, 1);
  ml_tensors_info_set_tensor_type(info, 0, ML_TENSOR_TYPE_FLOAT32);
  ml_tensors_info_set_tensor_dimension(info, 0, dim);
  return info;
}

/* The first output value of invoking h with all inputs set to v (NAN-free test values). */
static float invoke_first(ml_single_h h, float v) {
  ml_tensors_info_h info = NULL;
  ml_tensors_data_h in = NULL, out = NULL;
  void *raw = NULL;
  size_t size = 0;
  float r = -1;
  if (ml_single_get_input_info(h, &info) != ML_ERROR_NONE) return -1;
  ml_tensors_data_create(info, &in);
  ml_tensors_data_get_tensor_data(in, 0, &raw, &size);
  for (size_t k = 0; k < size / sizeof(float); ++k) ((float *)raw)[k] = v;
  if (ml_single_invoke(h, in, &out) == ML_ERROR_NONE) {
    ml_tensors_data_get_tensor_data(out, 0, &raw, &size);
    r = ((float *)raw)[0];
    ml_tensors_data_destroy(out);
  }
  ml_tensors_data_destroy(in);
  ml_tensors_info_destroy(info);
  return r;
}

static ml_single_h open_easy(const char *name) {
  ml_single_h h = NULL;
  ml_option_h opt = NULL;
  ml_option_create(&opt);
  ml_option_set(opt, "models", (void *)name, NULL);
  ml_option_set(opt, "framework_name", (void *)"custom-easy", NULL);
  CHECK(ml_single_open_with_option(&h, opt) == ML_ERROR_NONE);
  ml_option_destroy(opt);
  return h;
}

static void test_invoke(void) {
  ml_single_h h = NULL;
  ml_tensors_info_h in_info = NULL, out_info = NULL;
  ml_tensors_data_h in = NULL, out = NULL, out2 = NULL;
  ml_tensor_dimension dim;
  ml_tensor_type_e type;
  unsigned count = 0;
  size_t size = 0;
  void *raw = NULL;
  float v[6] = {0.5f, 1, 2, 3, 4, -5};

  CHECK(ml_single_open(&h, "c_double", NULL, NULL, ML_NNFW_TYPE_ANY, ML_NNFW_HW_ANY) !=
        ML_ERROR_NONE); /* "auto" cannot guess a registered name: must fail cleanly */
  h = open_easy("c_double");
  if (!h) return;
  CHECK(ml_single_get_input_info(h, &in_info) == ML_ERROR_NONE);
  CHECK(ml_tensors_info_get_tensor_size(in_info, 0, &size) == ML_ERROR_NONE && size == 24);
  CHECK(ml_single_get_output_info(h, &out_info) == ML_ERROR_NONE);
  CHECK(ml_tensors_info_get_count(out_info, &count) == ML_ERROR_NONE && count == 1);
  CHECK(ml_tensors_info_get_tensor_type(out_info, 0, &type) == ML_ERROR_NONE &&
        type == ML_TENSOR_TYPE_FLOAT32);
  CHECK(ml_tensors_info_get_tensor_dimension(out_info, 0, dim) == ML_ERROR_NONE && dim[0] == 3 &&
        dim[1] == 2);
  CHECK(ml_tensors_data_create(in_info, &in) == ML_ERROR_NONE);
  CHECK(ml_tensors_data_set_tensor_data(in, 0, v, sizeof v) == ML_ERROR_NONE);
  CHECK(ml_single_invoke(h, in, &out) == ML_ERROR_NONE);
  CHECK(ml_tensors_data_get_tensor_data(out, 0, &raw, &size) == ML_ERROR_NONE && size == 24);
  if (raw) CHECK(((float *)raw)[0] == 1.0f && ((float *)raw)[5] == -10.0f);
  /* invoke_fast into output made from the output info */
  CHECK(ml_tensors_data_create(out_info, &out2) == ML_ERROR_NONE);
  CHECK(ml_single_invoke_fast(h, in, out2) == ML_ERROR_NONE);
  raw = NULL;
  CHECK(ml_tensors_data_get_tensor_data(out2, 0, &raw, &size) == ML_ERROR_NONE && size == 24);
  if (raw) CHECK(((float *)raw)[2] == 4.0f && ((float *)raw)[4] == 8.0f);
  CHECK(ml_single_invoke_fast(h, in, NULL) == ML_ERROR_INVALID_PARAMETER);
  ml_tensors_data_destroy(out2);
  ml_tensors_data_destroy(out);
  ml_tensors_data_destroy(in);
  ml_tensors_info_destroy(in_info);
  ml_tensors_info_destroy(out_info);
  CHECK(ml_single_close(h) == ML_ERROR_NONE);
  CHECK(ml_single_close(NULL) == ML_ERROR_INVALID_PARAMETER);
}

static void test_timeout(void) {
  ml_single_h h = open_easy("c_slow");
  ml_tensors_info_h info = NULL;
  ml_tensors_data_h in = NULL, out = NULL;
  void *raw = NULL;
  size_t size = 0;
  int rc = ML_ERROR_TRY_AGAIN, tries;
  float v[6] = {1, 2, 3, 4, 5, 6};
  if (!h) return;
  ml_single_get_input_info(h, &info);
  ml_tensors_data_create(info, &in);
  ml_tensors_data_set_tensor_data(in, 0, v, sizeof v);
  CHECK(ml_single_set_timeout(h, 20) == ML_ERROR_NONE);
  CHECK(ml_single_invoke(h, in, &out) == ML_ERROR_TIMED_OUT);
  CHECK(strstr(ml_error(), "did not finish within 20 ms") != NULL);
  /* The late call still runs (300 ms): the handle is busy until it ends. */
  CHECK(ml_single_invoke(h, in, &out) == ML_ERROR_TRY_AGAIN);
  CHECK(ml_single_set_timeout(h, 10000) == ML_ERROR_NONE);
  for (tries = 0; tries < 200 && rc == ML_ERROR_TRY_AGAIN; ++tries) {
    rc = ml_single_invoke(h, in, &out);
    if (rc == ML_ERROR_TRY_AGAIN) sleep_ms(50);
  }
  CHECK(rc == ML_ERROR_NONE);
  if (rc == ML_ERROR_NONE) {
    CHECK(ml_tensors_data_get_tensor_data(out, 0, &raw, &size) == ML_ERROR_NONE);
    CHECK(raw && ((float *)raw)[5] == 12.0f);
    ml_tensors_data_destroy(out);
  }
  ml_tensors_data_destroy(in);
  ml_tensors_info_destroy(info);
  CHECK(ml_single_close(h) == ML_ERROR_NONE);
}

static void test_dynamic(void) {
  ml_single_h h = open_easy("c_sum");
  ml_tensors_info_h in_info = NULL, out_info = NULL, cur = NULL;
  ml_tensors_data_h in = NULL, out = NULL;
  ml_tensor_dimension dim;
  unsigned count = 1;
  void *raw = NULL;
  size_t size = 0;
  float v[5] = {1, 2, 3, 4, 5.5f};
  if (!h) return;
  /* The output is decided per call: no output tensors before the first. */
  CHECK(ml_single_get_output_info(h, &cur) == ML_ERROR_NONE);
  CHECK(ml_tensors_info_get_count(cur, &count) == ML_ERROR_NONE && count == 0);
  ml_tensors_info_destroy(cur);

  in_info = f32_info(5, 0);
  ml_tensors_data_create(in_info, &in);
  ml_tensors_data_set_tensor_data(in, 0, v, sizeof v);
  CHECK(ml_single_invoke_dynamic(h, in, in_info, &out, &out_info) == ML_ERROR_NONE);
  CHECK(ml_tensors_info_get_tensor_dimension(out_info, 0, dim) == ML_ERROR_NONE && dim[0] == 2);
  CHECK(ml_tensors_data_get_tensor_data(out, 0, &raw, &size) == ML_ERROR_NONE && size == 8);
  if (raw) CHECK(((float *)raw)[0] == 15.5f && ((float *)raw)[1] == 5.0f);
  ml_tensors_data_destroy(out);
  ml_tensors_info_destroy(out_info);
  ml_tensors_data_destroy(in);
  ml_tensors_info_destroy(in_info);

  /* Another shape: 2x2, through the time-out worker this time */
  CHECK(ml_single_set_timeout(h, 10000) == ML_ERROR_NONE);
  in_info = f32_info(2, 2);
  ml_tensors_data_create(in_info, &in);
  ml_tensors_data_set_tensor_data(in, 0, v, 4 * sizeof(float));
  CHECK(ml_single_invoke_dynamic(h, in, in_info, &out, &out_info) == ML_ERROR_NONE);
  raw = NULL;
  CHECK(ml_tensors_data_get_tensor_data(out, 0, &raw, &size) == ML_ERROR_NONE && size == 8);
  if (raw) CHECK(((float *)raw)[0] == 10.0f && ((float *)raw)[1] == 4.0f);
  CHECK(ml_single_get_input_info(h, &cur) == ML_ERROR_NONE);
  CHECK(ml_tensors_info_get_tensor_dimension(cur, 0, dim) == ML_ERROR_NONE && dim[0] == 2 &&
        dim[1] == 2);
  ml_tensors_info_destroy(cur);
  ml_tensors_data_destroy(out);
  ml_tensors_info_destroy(out_info);
  CHECK(ml_single_invoke_dynamic(h, in, NULL, &out, &out_info) == ML_ERROR_INVALID_PARAMETER);
  ml_tensors_data_destroy(in);
  ml_tensors_info_destroy(in_info);
  CHECK(ml_single_close(h) == ML_ERROR_NONE);
}

static void test_set_input_info_and_properties(void) {
  ml_single_h h = open_easy("c_double");
  ml_tensors_info_h same = NULL, other = f32_info(4, 4);
  char *value = NULL;
  if (!h) return;
  CHECK(ml_single_get_input_info(h, &same) == ML_ERROR_NONE);
  CHECK(ml_single_set_input_info(h, same) == ML_ERROR_NONE);
  /* custom-easy models have fixed shapes */
  CHECK(ml_single_set_input_info(h, other) == ML_ERROR_NOT_SUPPORTED);
  CHECK(strstr(ml_single_get_last_error(h), "cannot change its input") != NULL);
  CHECK(ml_single_set_input_info(h, NULL) == ML_ERROR_INVALID_PARAMETER);

  CHECK(ml_single_get_property(h, "input", &value) == ML_ERROR_NONE && value &&
        strcmp(value, "3:2") == 0);
  free(value);
  CHECK(ml_single_get_property(h, "inputtype", &value) == ML_ERROR_NONE && value &&
        strcmp(value, "float32") == 0);
  free(value);
  CHECK(ml_single_get_property(h, "no-such-property", &value) == ML_ERROR_NOT_SUPPORTED);
  CHECK(ml_single_set_property(h, "framework", "custom") == ML_ERROR_NOT_SUPPORTED);
  CHECK(ml_single_set_property(h, "inputtype", "float64") == ML_ERROR_NOT_SUPPORTED);
  /* model reload: refused until is-updatable is true */
  CHECK(ml_single_set_property(h, "model", "c_triple") == ML_ERROR_NOT_SUPPORTED);
  CHECK(invoke_first(h, 2.0f) == 4.0f);
  CHECK(ml_single_set_property(h, "is-updatable", "true") == ML_ERROR_NONE);
  CHECK(ml_single_set_property(h, "model", "c_triple") == ML_ERROR_NONE);
  CHECK(ml_single_get_property(h, "model", &value) == ML_ERROR_NONE && value &&
        strcmp(value, "c_triple") == 0);
  free(value);
  CHECK(invoke_first(h, 2.0f) == 6.0f);
  CHECK(ml_single_set_property(h, "inputname", "x") == ML_ERROR_NONE);
  CHECK(ml_single_get_property(h, "inputname", &value) == ML_ERROR_NONE && value &&
        strcmp(value, "x") == 0);
  free(value);
  ml_tensors_info_destroy(same);
  ml_tensors_info_destroy(other);
  CHECK(ml_single_close(h) == ML_ERROR_NONE);
}

/* LeNet on PyTorch: ../shared/models/upstream/data/9.raw is a 9. */
static int lenet_class(ml_single_h h, const unsigned char *digit) {
  ml_tensors_info_h info = NULL;
  ml_tensors_data_h in = NULL, out = NULL;
  void *raw = NULL;
  size_t size = 0;
  int best = -1;
  ml_single_get_input_info(h, &info);
  ml_tensors_data_create(info, &in);
  ml_tensors_data_set_tensor_data(in, 0, digit, 28 * 28);
  if (ml_single_invoke(h, in, &out) == ML_ERROR_NONE &&
      ml_tensors_data_get_tensor_data(out, 0, &raw, &size) == ML_ERROR_NONE && size == 10) {
    const unsigned char *s = raw;
    best = 0;
    for (int i = 1; i < 10; ++i)
      if (s[i] > s[best]) best = i;
  }
  ml_tensors_data_destroy(out);
  ml_tensors_data_destroy(in);
  ml_tensors_info_destroy(info);
  return best;
}

static void test_lenet(void) {
  const char *model = NNS_SOURCE_DIR "/../shared/models/upstream/models/pytorch_lenet5.pt";
  const char *data = NNS_SOURCE_DIR "/../shared/models/upstream/data/9.raw";
  const char *so = NNS_BUILD_DIR "/subplugins/filters/libnnstreamer_filter_pytorch.so";
  unsigned char digit[28 * 28];
  ml_tensor_dimension din = {1, 28, 28, 1}, dout = {10, 1};
  ml_tensors_info_h in = NULL, out = NULL;
  ml_single_h h = NULL;
  ml_option_h opt = NULL;
  ml_nnfw_type_e nnfw = ML_NNFW_TYPE_PYTORCH;
  ml_nnfw_hw_e hw = ML_NNFW_HW_CPU;
  char *value = NULL;
  FILE *f;
  if (access(model, R_OK) != 0 || access(so, R_OK) != 0) {
    printf("SKIP LeNet: %s or %s is missing\n", model, so);
    return;
  }
  f = fopen(data, "rb");
  CHECK(f && fread(digit, 1, sizeof digit, f) == sizeof digit);
  if (f) fclose(f);
  ml_tensors_info_create(&in);
  ml_tensors_info_set_count(in, 1);
  ml_tensors_info_set_tensor_type(in, 0, ML_TENSOR_TYPE_UINT8);
  ml_tensors_info_set_tensor_dimension(in, 0, din);
  ml_tensors_info_create(&out);
  ml_tensors_info_set_count(out, 1);
  ml_tensors_info_set_tensor_type(out, 0, ML_TENSOR_TYPE_UINT8);
  ml_tensors_info_set_tensor_dimension(out, 0, dout);

  CHECK(ml_single_open_full(&h, model, in, out, ML_NNFW_TYPE_PYTORCH, ML_NNFW_HW_ANY,
                            "NumThreads:1") == ML_ERROR_NONE);
  if (h) {
    CHECK(lenet_class(h, digit) == 9);
    CHECK(ml_single_get_property(h, "custom", &value) == ML_ERROR_NONE && value &&
          strcmp(value, "NumThreads:1") == 0);
    free(value);
    CHECK(ml_single_close(h) == ML_ERROR_NONE);
  }
  h = NULL;
  CHECK(ml_single_open_full(&h, model, in, out, ML_NNFW_TYPE_PYTORCH, ML_NNFW_HW_ANY,
                            "NoSuchKey:1") == ML_ERROR_STREAMS_PIPE);
  CHECK(h == NULL && strstr(ml_error(), "NoSuchKey") != NULL);

  ml_option_create(&opt);
  ml_option_set(opt, "models", (void *)model, NULL);
  ml_option_set(opt, "nnfw", &nnfw, NULL);
  ml_option_set(opt, "hw", &hw, NULL);
  ml_option_set(opt, "input_info", in, NULL);
  ml_option_set(opt, "output_info", out, NULL);
  CHECK(ml_single_open_with_option(&h, opt) == ML_ERROR_NONE);
  ml_option_destroy(opt);
  if (h) {
    CHECK(lenet_class(h, digit) == 9);
    CHECK(ml_single_get_property(h, "accelerator", &value) == ML_ERROR_NONE && value &&
          strcmp(value, "true:cpu") == 0);
    free(value);
    CHECK(ml_single_close(h) == ML_ERROR_NONE);
  }
  ml_tensors_info_destroy(in);
  ml_tensors_info_destroy(out);
}

int main(void) {
  GstTensorsInfo info;
  memset(&info, 0, sizeof info);
  info.num_tensors = 1;
  info.info[0].type = _NNS_FLOAT32;
  info.info[0].dimension[0] = 3;
  info.info[0].dimension[1] = 2;
  CHECK(NNS_custom_easy_register("c_double", double_it, NULL, &info, &info) == 0);
  CHECK(NNS_custom_easy_register("c_triple", triple_it, NULL, &info, &info) == 0);
  CHECK(NNS_custom_easy_register("c_slow", slow_double, NULL, &info, &info) == 0);
  CHECK(NNS_custom_easy_dynamic_register("c_sum", sum_count, NULL, &info) == 0);

  test_invoke();
  test_timeout();
  test_dynamic();
  test_set_input_info_and_properties();
  test_lenet();
  printf("%d passed, %d failed\n", passed, failed);
  return failed ? 1 : 0;
}
