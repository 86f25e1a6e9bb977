/* SPDX-License-Identifier: LGPL-2.1-only */
/* Built against NNStreamer's library names only (-lcapi-ml-inference-single, tests/api_pipeline
 * .cmake): the common and single-shot functions resolve through them. Exit 0 when they work. */
#include <stdio.h>

#include "ml-api-common.h"
#include "nnstreamer-single.h"

int main(void) {
  ml_tensors_info_h info = NULL;
  unsigned int count = 0;
  ml_tensor_dimension dim = {3, 224, 224, 1};
  ml_tensor_dimension back = {0};
  if (ml_tensors_info_create(&info) != ML_ERROR_NONE) return 1;
  if (ml_tensors_info_set_count(info, 1) != ML_ERROR_NONE) return 2;
  if (ml_tensors_info_set_tensor_dimension(info, 0, dim) != ML_ERROR_NONE) return 3;
  if (ml_tensors_info_get_count(info, &count) != ML_ERROR_NONE || count != 1) return 4;
  if (ml_tensors_info_get_tensor_dimension(info, 0, back) != ML_ERROR_NONE || back[1] != 224)
    return 5;
  ml_tensors_info_destroy(info);
  /* A model that does not exist: the single-shot API answers with an error code, no crash. */
  ml_single_h single = NULL;
  if (ml_single_open(&single, "/nonexistent/model.onnx", NULL, NULL, ML_NNFW_TYPE_ANY,
                     ML_NNFW_HW_ANY) == ML_ERROR_NONE)
    return 6;
  printf("ml api through libcapi-ml-inference-single: ok\n");
  return 0;
}
