/* SPDX-License-Identifier: LGPL-2.1-only */
/* The single-shot ML API from C against the installed packages (checks.sh compiles it with
 * `pkg-config --cflags --libs capi-ml-inference`): LeNet on PyTorch classifies a 28x28 digit.
 * usage: ml_api_check <pytorch_lenet5.pt> <digit.raw>; prints "class N", exits 0 when it ran. */
#include <stdio.h>

#include <nnstreamer-single.h>

int main(int argc, char **argv) {
  unsigned char digit[28 * 28];
  ml_tensor_dimension din = {1, 28, 28, 1}, dout = {10, 1};
  ml_tensors_info_h in = NULL, out = NULL, info = NULL;
  ml_tensors_data_h input = NULL, output = NULL;
  ml_single_h h = NULL;
  void *raw = NULL;
  size_t size = 0;
  int best = -1;
  FILE *f;
  if (argc != 3) return 2;
  f = fopen(argv[2], "rb");
  if (!f || fread(digit, 1, sizeof digit, f) != sizeof digit) {
    fprintf(stderr, "cannot read %s\n", argv[2]);
    return 1;
  }
  fclose(f);
  ml_tensors_info_create(&in);
  ml_tensors_info_set_count(in, 1);
  ml_tensors_info_set_tensor_type(in, 0, ML_TENSOR_TYPE_UINT8);
  ml_tensors_info_set_tensor_dimension(in, 0, din);
  ml_tensors_info_create(&out);
  ml_tensors_info_set_count(out, 1);
  ml_tensors_info_set_tensor_type(out, 0, ML_TENSOR_TYPE_UINT8);
  ml_tensors_info_set_tensor_dimension(out, 0, dout);
  if (ml_single_open(&h, argv[1], in, out, ML_NNFW_TYPE_PYTORCH, ML_NNFW_HW_ANY) != ML_ERROR_NONE) {
    fprintf(stderr, "ml_single_open: %s\n", ml_error());
    return 1;
  }
  ml_single_get_input_info(h, &info);
  ml_tensors_data_create(info, &input);
  ml_tensors_data_set_tensor_data(input, 0, digit, sizeof digit);
  if (ml_single_invoke(h, input, &output) == ML_ERROR_NONE &&
      ml_tensors_data_get_tensor_data(output, 0, &raw, &size) == ML_ERROR_NONE && size == 10) {
    const unsigned char *s = raw;
    best = 0;
    for (int i = 1; i < 10; ++i)
      if (s[i] > s[best]) best = i;
  } else {
    fprintf(stderr, "ml_single_invoke: %s\n", ml_error());
  }
  printf("class %d\n", best);
  ml_tensors_data_destroy(output);
  ml_tensors_data_destroy(input);
  ml_tensors_info_destroy(info);
  ml_tensors_info_destroy(in);
  ml_tensors_info_destroy(out);
  ml_single_close(h);
  return best < 0;
}
