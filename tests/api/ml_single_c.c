/* SPDX-License-Identifier: LGPL-2.1-only */
/* The single-shot API from plain C: open a custom-easy model, invoke, check, close.
 * Prints "N passed, N failed" and exits non-zero on failure. */
#include <stdio.h>
#include <string.h>

#include "nnstreamer-single.h"
#include "tensor_filter_custom_easy.h"

static int passed, failed;
#define CHECK(cond)                                                      \
  do {                                                                   \
    if (cond) {                                                          \
      ++passed;                                                          \
    } else {                                                             \
      ++failed;                                                          \
      fprintf(stderr, "%s:%d: %s failed (%s)\n", __FILE__, __LINE__, #cond, ml_error()); \
    }                                                                    \
  } while (0)

static int double_it(void *data, const GstTensorFilterProperties *prop, const GstTensorMemory *in,
                     GstTensorMemory *out) {
  const float *i = (const float *)in[0].data;
  float *o = (float *)out[0].data;
  (void)data;
  (void)prop;
  for (size_t k = 0; k < in[0].size / sizeof(float); ++k) o[k] = 2.0f * i[k];
  return 0;
}

int main(void) {
  GstTensorsInfo info;
  memset(&info, 0, sizeof info);
  info.num_tensors = 1;
  info.info[0].type = _NNS_FLOAT32;
  info.info[0].dimension[0] = 3;
  info.info[0].dimension[1] = 2;
  CHECK(NNS_custom_easy_register("c_double", double_it, NULL, &info, &info) == 0);

  ml_single_h h = NULL;
  CHECK(ml_single_open(&h, "c_double", NULL, NULL, ML_NNFW_TYPE_ANY, ML_NNFW_HW_ANY) !=
        ML_ERROR_NONE); /* "auto" cannot guess a registered name: must fail cleanly */
  ml_option_h opt = NULL;
  CHECK(ml_option_create(&opt) == ML_ERROR_NONE);
  CHECK(ml_option_set(opt, "models", (void *)"c_double", NULL) == ML_ERROR_NONE);
  CHECK(ml_option_set(opt, "framework_name", (void *)"custom-easy", NULL) == ML_ERROR_NONE);
  CHECK(ml_single_open_with_option(&h, opt) == ML_ERROR_NONE);
  ml_option_destroy(opt);
  if (!h) {
    printf("%d passed, %d failed\n", passed, failed + 1);
    return 1;
  }
  ml_tensors_info_h in_info = NULL;
  CHECK(ml_single_get_input_info(h, &in_info) == ML_ERROR_NONE);
  size_t size = 0;
  CHECK(ml_tensors_info_get_tensor_size(in_info, 0, &size) == ML_ERROR_NONE && size == 24);
  ml_tensors_data_h in = NULL, out = NULL;
  CHECK(ml_tensors_data_create(in_info, &in) == ML_ERROR_NONE);
  float v[6] = {0.5f, 1, 2, 3, 4, -5};
  CHECK(ml_tensors_data_set_tensor_data(in, 0, v, sizeof v) == ML_ERROR_NONE);
  CHECK(ml_single_invoke(h, in, &out) == ML_ERROR_NONE);
  void *raw = NULL;
  CHECK(ml_tensors_data_get_tensor_data(out, 0, &raw, &size) == ML_ERROR_NONE && size == 24);
  if (raw) {
    const float *o = (const float *)raw;
    CHECK(o[0] == 1.0f && o[5] == -10.0f);
  }
  ml_tensors_data_destroy(out);
  ml_tensors_data_destroy(in);
  ml_tensors_info_destroy(in_info);
  CHECK(ml_single_close(h) == ML_ERROR_NONE);
  CHECK(ml_single_close(NULL) == ML_ERROR_INVALID_PARAMETER);
  printf("%d passed, %d failed\n", passed, failed);
  return failed ? 1 : 0;
}
