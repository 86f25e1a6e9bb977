/* SPDX-License-Identifier: LGPL-2.1-only */
/* A program written as NNStreamer 2.x code that drives frameworks directly (as NNStreamer's
 * ML API library, tools and tests do): C, NNStreamer's installed headers only, linked to
 * libnnstreamer.so. For each of our back ends it calls nnstreamer_filter_find(), checks the
 * version-1 table, opens a real model, reads its tensors, invokes it and compares the output,
 * then closes it. Also: invoke-dynamic, allocate-in-invoke with DESTROY_NOTIFY, statistics,
 * CHECK_HW_AVAILABILITY, the same table on every call, and the decoder/converter lookups.
 *
 * usage: find_frameworks <shared models dir (…/upstream)> <source dir> <test filter dir>
 * A back end whose libnnstreamer_filter_<name>.so is not in $NNSTREAMER_FILTERS is skipped
 * (printed); one that is there must work. Exit 0: every case passed; 1: a failure. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "nnstreamer_plugin_api_converter.h"
#include "nnstreamer_plugin_api_decoder.h"
#include "nnstreamer_plugin_api_filter.h"
#include "nnstreamer_plugin_api_util.h"
#include "tensor_filter_custom_easy.h"
#include <gst/gst.h>

static int g_failed;
static const char *g_models, *g_src, *g_filters;

#define CHECK(cond, ...)                                   \
  do {                                                     \
    if (!(cond)) {                                         \
      fprintf(stderr, "FAIL %s:%d: ", __FILE__, __LINE__); \
      fprintf(stderr, __VA_ARGS__);                        \
      fprintf(stderr, "\n");                               \
      g_failed = 1;                                        \
      return;                                              \
    }                                                      \
  } while (0)

static int have_backend(const char *name) {
  const char *dirs = getenv("NNSTREAMER_FILTERS");
  char buf[4096], path[4200];
  if (!dirs) return 0;
  snprintf(buf, sizeof buf, "%s", dirs);
  for (char *save = NULL, *d = strtok_r(buf, ":", &save); d; d = strtok_r(NULL, ":", &save)) {
    snprintf(path, sizeof path, "%s/libnnstreamer_filter_%s.so", d, name);
    if (access(path, R_OK) == 0) return 1;
  }
  return 0;
}

static void *read_file(const char *dir, const char *name, size_t want) {
  char path[4200];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  void *b = malloc(want);
  size_t n = fread(b, 1, want, f);
  fclose(f);
  if (n != want) {
    free(b);
    return NULL;
  }
  return b;
}

static int file_exists(const char *dir, const char *name) {
  char path[4200];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  return access(path, R_OK) == 0;
}

static void set_info(GstTensorsInfo *info, unsigned i, tensor_type t, const char *dims) {
  GstTensorInfo *ti = gst_tensors_info_get_nth_info(info, i);
  ti->type = t;
  gst_tensor_parse_dimension(dims, ti->dimension);
  if (info->num_tensors < i + 1) info->num_tensors = i + 1;
}

/* An opened framework: the table, the properties and the private data. */
typedef struct {
  const GstTensorFilterFramework *fw;
  GstTensorFilterProperties prop;
  const char *models[2];
  void *priv;
} Opened;

static int open_fw(Opened *o, const char *name, const char *m0, const char *m1,
                   const char *custom) {
  memset(o, 0, sizeof *o);
  o->fw = nnstreamer_filter_find(name);
  if (!o->fw) {
    fprintf(stderr, "FAIL: nnstreamer_filter_find(\"%s\") returned NULL\n", name);
    g_failed = 1;
    return -1;
  }
  if (o->fw != nnstreamer_filter_find(name)) {
    fprintf(stderr, "FAIL: %s: a second find returned another table\n", name);
    g_failed = 1;
    return -1;
  }
  if (!checkGstTensorFilterFrameworkVersion(o->fw->version, 1) || !o->fw->open || !o->fw->close ||
      !o->fw->invoke || !o->fw->getFrameworkInfo || !o->fw->getModelInfo || !o->fw->eventHandler) {
    fprintf(stderr, "FAIL: %s: not a complete version-1 table\n", name);
    g_failed = 1;
    return -1;
  }
  GstTensorFilterFrameworkInfo info;
  memset(&info, 0, sizeof info);
  o->prop.fwname = name;
  if (o->fw->getFrameworkInfo(o->fw, &o->prop, NULL, &info) != 0 || !info.name || info.num_hw < 1 ||
      !info.hw_list) {
    fprintf(stderr, "FAIL: %s: getFrameworkInfo before open\n", name);
    g_failed = 1;
    return -1;
  }
  GstTensorFilterFrameworkEventData ev;
  memset(&ev, 0, sizeof ev);
  ev.hw = ACCL_CPU;
  if (o->fw->eventHandler(o->fw, &o->prop, NULL, CHECK_HW_AVAILABILITY, &ev) != 0) {
    fprintf(stderr, "FAIL: %s: CHECK_HW_AVAILABILITY(cpu) refused\n", name);
    g_failed = 1;
    return -1;
  }
  o->models[0] = m0;
  o->models[1] = m1;
  o->prop.model_files = o->models;
  o->prop.num_models = m1 ? 2 : 1;
  o->prop.custom_properties = custom;
  gst_tensors_info_init(&o->prop.input_meta);
  gst_tensors_info_init(&o->prop.output_meta);
  int rc = o->fw->open(&o->prop, &o->priv);
  if (rc != 0) {
    fprintf(stderr, "FAIL: %s: open(%s) returned %d\n", name, m0, rc);
    g_failed = 1;
    return -1;
  }
  o->prop.fw_opened = 1;
  return 0;
}

/* Statistics count the invokes; then close. */
static void close_fw(Opened *o, int invokes) {
  GstTensorFilterFrameworkInfo info;
  memset(&info, 0, sizeof info);
  if (o->fw->getFrameworkInfo(o->fw, &o->prop, o->priv, &info) != 0 || !info.statistics ||
      info.statistics->total_invoke_num != invokes) {
    fprintf(stderr, "FAIL: %s: statistics after %d invokes: %lld\n", o->prop.fwname, invokes,
            info.statistics ? (long long)info.statistics->total_invoke_num : -1LL);
    g_failed = 1;
  }
  o->fw->close(&o->prop, &o->priv);
  if (o->priv) {
    fprintf(stderr, "FAIL: %s: close left private data\n", o->prop.fwname);
    g_failed = 1;
  }
  gst_tensors_info_free(&o->prop.input_meta);
  gst_tensors_info_free(&o->prop.output_meta);
}

/* GET_IN_OUT_INFO into prop's metas; returns 0. */
static int model_info(Opened *o) {
  return o->fw->getModelInfo(o->fw, &o->prop, o->priv, GET_IN_OUT_INFO, &o->prop.input_meta,
                             &o->prop.output_meta);
}

static int argmax_u8(const uint8_t *p, int n) {
  int best = 0;
  for (int i = 1; i < n; ++i)
    if (p[i] > p[best]) best = i;
  return best;
}

static int argmax_f(const float *p, int n) {
  int best = 0;
  for (int i = 1; i < n; ++i)
    if (p[i] > p[best]) best = i;
  return best;
}

/* ---- custom-easy: x * 2 (float32 4), and an invoke-dynamic model ------------------------ */

static int cx_double(void *data, const GstTensorFilterProperties *prop, const GstTensorMemory *in,
                     GstTensorMemory *out) {
  (void)data;
  (void)prop;
  const float *x = in[0].data;
  float *y = out[0].data;
  for (int i = 0; i < 4; ++i) y[i] = x[i] * 2.f;
  return 0;
}

/* Output: float32 N = in / 2 for a uint8 N input, allocated here. */
static int cx_dyn(void *data, const GstTensorsInfo *in_info, GstTensorsInfo *out_info,
                  const GstTensorMemory *input, GstTensorMemory *output) {
  (void)data;
  (void)in_info;
  uint32_t n = (uint32_t)input[0].size;
  float *y = malloc(n * sizeof(float));
  for (uint32_t i = 0; i < n; ++i) y[i] = ((const uint8_t *)input[0].data)[i] / 2.f;
  gst_tensors_info_init(out_info);
  out_info->num_tensors = 1;
  out_info->info[0].type = _NNS_FLOAT32;
  out_info->info[0].dimension[0] = n;
  out_info->info[0].dimension[1] = 1;
  output[0].data = y;
  output[0].size = n * sizeof(float);
  return 0;
}

static void case_custom_easy(void) {
  GstTensorsInfo in, out;
  gst_tensors_info_init(&in);
  gst_tensors_info_init(&out);
  set_info(&in, 0, _NNS_FLOAT32, "4:1");
  set_info(&out, 0, _NNS_FLOAT32, "4:1");
  CHECK(NNS_custom_easy_register("cx_double", cx_double, NULL, &in, &out) == 0, "register");
  Opened o;
  if (open_fw(&o, "custom-easy", "cx_double", NULL, NULL)) return;
  CHECK(model_info(&o) == 0, "custom-easy: getModelInfo");
  CHECK(o.prop.input_meta.num_tensors == 1 && o.prop.input_meta.info[0].type == _NNS_FLOAT32 &&
            o.prop.input_meta.info[0].dimension[0] == 4,
        "custom-easy: input info");
  float x[4] = {1.f, -2.5f, 0.f, 100.f}, y[4] = {0};
  GstTensorMemory im = {x, sizeof x}, om = {y, sizeof y};
  CHECK(o.fw->invoke(o.fw, &o.prop, o.priv, &im, &om) == 0, "custom-easy: invoke");
  CHECK(y[0] == 2.f && y[1] == -5.f && y[2] == 0.f && y[3] == 200.f, "custom-easy: values");
  close_fw(&o, 1);
  gst_tensors_info_free(&in);
  gst_tensors_info_free(&out);

  /* invoke-dynamic: the framework allocates and describes the output in prop->output_meta;
   * DESTROY_NOTIFY releases it. */
  GstTensorsInfo din;
  gst_tensors_info_init(&din);
  set_info(&din, 0, _NNS_UINT8, "3:1");
  CHECK(NNS_custom_easy_dynamic_register("cx_dyn", cx_dyn, NULL, &din) == 0, "dyn register");
  if (open_fw(&o, "custom-easy", "cx_dyn", NULL, NULL)) return;
  o.prop.invoke_dynamic = 1;
  gst_tensors_info_copy(&o.prop.input_meta, &din);
  uint8_t b[3] = {2, 5, 255};
  GstTensorMemory dim = {b, 3}, dom[NNS_TENSOR_MEMORY_MAX];
  memset(dom, 0, sizeof dom);
  CHECK(o.fw->invoke(o.fw, &o.prop, o.priv, &dim, dom) == 0, "custom-easy: dynamic invoke");
  CHECK(o.prop.output_meta.num_tensors == 1 && o.prop.output_meta.info[0].type == _NNS_FLOAT32 &&
            o.prop.output_meta.info[0].dimension[0] == 3,
        "custom-easy: dynamic output_meta");
  const float *d = dom[0].data;
  CHECK(d && dom[0].size == 12 && d[0] == 1.f && d[1] == 2.5f && d[2] == 127.5f,
        "custom-easy: dynamic values");
  GstTensorFilterFrameworkEventData ev;
  memset(&ev, 0, sizeof ev);
  ev.data = dom[0].data;
  CHECK(o.fw->eventHandler(o.fw, &o.prop, o.priv, DESTROY_NOTIFY, &ev) == 0, "DESTROY_NOTIFY");
  close_fw(&o, 1);
  gst_tensors_info_free(&din);
  printf("ok custom-easy (static and invoke-dynamic)\n");
}

/* ---- custom: the scaler test filter (setInputDim, allocate_invoke + destroy_notify) ----- */

static void case_custom(void) {
  char lib[4200];
  snprintf(lib, sizeof lib, "%s/libcustom_scaler.so", g_filters);
  if (access(lib, R_OK) != 0) {
    printf("skip custom: %s not built\n", lib);
    return;
  }
  Opened o;
  if (open_fw(&o, "custom", lib, NULL, "2x2")) return;
  GstTensorsInfo out;
  gst_tensors_info_init(&out);
  set_info(&o.prop.input_meta, 0, _NNS_UINT8, "1:4:4:1");
  CHECK(o.fw->getModelInfo(o.fw, &o.prop, o.priv, SET_INPUT_INFO, &o.prop.input_meta, &out) == 0,
        "custom: SET_INPUT_INFO");
  CHECK(out.num_tensors == 1 && out.info[0].dimension[1] == 2 && out.info[0].dimension[2] == 2,
        "custom: output 1:2:2");
  gst_tensors_info_copy(&o.prop.output_meta, &out);
  GstTensorFilterFrameworkInfo info;
  memset(&info, 0, sizeof info);
  CHECK(o.fw->getFrameworkInfo(o.fw, &o.prop, o.priv, &info) == 0, "custom: info");
  uint8_t x[16], y[4] = {0};
  for (int i = 0; i < 16; ++i) x[i] = (uint8_t)(i * 10);
  GstTensorMemory im = {x, 16}, om = {info.allocate_in_invoke ? NULL : y, 4};
  CHECK(o.fw->invoke(o.fw, &o.prop, o.priv, &im, &om) == 0, "custom: invoke");
  const uint8_t *r = om.data;
  CHECK(r && om.size == 4, "custom: output memory");
  /* Nearest neighbour of a 4x4 ramp to 2x2: rows 0 and 2, columns 0 and 2. */
  CHECK(r[0] == 0 && r[1] == 20 && r[2] == 80 && r[3] == 100, "custom: values %u %u %u %u", r[0],
        r[1], r[2], r[3]);
  if (info.allocate_in_invoke) {
    GstTensorFilterFrameworkEventData ev;
    memset(&ev, 0, sizeof ev);
    ev.data = om.data;
    CHECK(o.fw->eventHandler(o.fw, &o.prop, o.priv, DESTROY_NOTIFY, &ev) == 0,
          "custom: DESTROY_NOTIFY");
  }
  close_fw(&o, 1);
  gst_tensors_info_free(&out);
  printf("ok custom (allocate_in_invoke=%d)\n", info.allocate_in_invoke);
}

/* ---- back ends with real models ------------------------------------------------------ */

/* mobilenet_v2_quant.onnx: float32 NCHW 1x3x224x224 with torchvision's normalisation, 1000
 * float32 scores; the orange gives 950 (tied with 951 at the quantized output's level). */
static void case_onnxruntime(void) {
  if (!have_backend("onnxruntime")) {
    printf("skip onnxruntime: not built\n");
    return;
  }
  char model[4200];
  snprintf(model, sizeof model, "%s/models/mobilenet_v2_quant.onnx", g_models);
  uint8_t *img = read_file(g_models, "data/orange.raw", 224 * 224 * 3);
  CHECK(img, "orange.raw missing");
  Opened o;
  if (open_fw(&o, "onnxruntime", model, NULL, "NumThreads:1")) return;
  CHECK(model_info(&o) == 0, "onnxruntime: getModelInfo");
  CHECK(o.prop.input_meta.info[0].type == _NNS_FLOAT32 &&
            gst_tensor_info_get_size(&o.prop.input_meta.info[0]) == 224 * 224 * 3 * 4,
        "onnxruntime: input float32 224:224:3:1");
  size_t osize = gst_tensor_info_get_size(&o.prop.output_meta.info[0]);
  CHECK(osize == 1000 * 4, "onnxruntime: output size %zu", osize);
  static const float mean[3] = {123.675f, 116.28f, 103.53f}, sd[3] = {58.395f, 57.12f, 57.375f};
  float *chw = malloc(3 * 224 * 224 * sizeof(float)), *scores = calloc(1000, sizeof(float));
  for (int y = 0; y < 224; ++y)
    for (int x = 0; x < 224; ++x)
      for (int c = 0; c < 3; ++c)
        chw[c * 224 * 224 + y * 224 + x] = (img[(y * 224 + x) * 3 + c] - mean[c]) / sd[c];
  GstTensorMemory im = {chw, 3 * 224 * 224 * sizeof(float)}, om = {scores, osize};
  int rc = o.fw->invoke(o.fw, &o.prop, o.priv, &im, &om);
  int best = argmax_f(scores, 1000);
  close_fw(&o, 1);
  free(chw);
  free(scores);
  free(img);
  CHECK(rc == 0, "onnxruntime: invoke");
  CHECK(best == 950, "onnxruntime: orange is 950, got %d", best);
  printf("ok onnxruntime (orange = 950)\n");
}

static void case_pytorch(void) {
  if (!have_backend("pytorch")) {
    printf("skip pytorch: not built\n");
    return;
  }
  char model[4200];
  snprintf(model, sizeof model, "%s/models/pytorch_lenet5.pt", g_models);
  uint8_t *img = read_file(g_models, "data/9.raw", 28 * 28);
  CHECK(img, "9.raw missing");
  Opened o;
  memset(&o, 0, sizeof o);
  /* pytorch needs the tensors from the caller (input=/output=): give them before open. */
  o.fw = nnstreamer_filter_find("pytorch");
  CHECK(o.fw, "pytorch: find");
  o.prop.fwname = "pytorch";
  o.models[0] = model;
  o.prop.model_files = o.models;
  o.prop.num_models = 1;
  gst_tensors_info_init(&o.prop.input_meta);
  gst_tensors_info_init(&o.prop.output_meta);
  set_info(&o.prop.input_meta, 0, _NNS_UINT8, "1:28:28:1");
  set_info(&o.prop.output_meta, 0, _NNS_UINT8, "10:1");
  CHECK(o.fw->open(&o.prop, &o.priv) == 0, "pytorch: open");
  uint8_t out[10] = {0};
  GstTensorMemory im = {img, 28 * 28}, om = {out, 10};
  CHECK(o.fw->invoke(o.fw, &o.prop, o.priv, &im, &om) == 0, "pytorch: invoke");
  int best = argmax_u8(out, 10);
  CHECK(best == 9, "pytorch: 9.raw is 9, got %d", best);
  close_fw(&o, 1);
  free(img);
  printf("ok pytorch (9.raw = 9)\n");
}

/* add.tflite (x + 2) through a TensorFlow Lite capable back end: armnn here, and
 * tensorflow-lite / tensorflow2-lite when such a back end is built. */
static void case_add_tflite(const char *name) {
  if (!have_backend(name)) {
    printf("skip %s: not built\n", name);
    return;
  }
  char model[4200];
  snprintf(model, sizeof model, "%s/models/add.tflite", g_models);
  Opened o;
  if (open_fw(&o, name, model, NULL, NULL)) return;
  CHECK(model_info(&o) == 0, "%s: getModelInfo", name);
  float x = 3.5f, y = 0.f;
  GstTensorMemory im = {&x, 4}, om = {&y, 4};
  CHECK(o.fw->invoke(o.fw, &o.prop, o.priv, &im, &om) == 0, "%s: invoke", name);
  CHECK(y == 5.5f, "%s: add.tflite 3.5 + 2 = %f", name, y);
  close_fw(&o, 1);
  printf("ok %s (add.tflite)\n", name);
}

static void case_opencv(void) {
  if (!have_backend("opencv")) {
    printf("skip opencv: not built\n");
    return;
  }
  char proto[4200], model[4200];
  snprintf(proto, sizeof proto, "%s/tests/data/lenet_deploy.prototxt", g_src);
  snprintf(model, sizeof model, "%s/models/lenet_iter_9000.caffemodel", g_models);
  uint8_t *raw = read_file(g_models, "data/9.raw", 28 * 28);
  CHECK(raw, "9.raw missing");
  Opened o;
  if (open_fw(&o, "opencv", proto, model, NULL)) return;
  CHECK(model_info(&o) == 0, "opencv: getModelInfo");
  float x[784], prob[10] = {0};
  for (int i = 0; i < 784; ++i) x[i] = (raw[i] - 127.5f) / 127.5f;
  GstTensorMemory im = {x, sizeof x}, om = {prob, sizeof prob};
  CHECK(o.fw->invoke(o.fw, &o.prop, o.priv, &im, &om) == 0, "opencv: invoke");
  int best = argmax_f(prob, 10);
  CHECK(best == 9, "opencv: lenet 9.raw is 9, got %d", best);
  close_fw(&o, 1);
  free(raw);
  printf("ok opencv (caffe lenet = 9)\n");
}

static void case_python3(void) {
  if (!have_backend("python3")) {
    printf("skip python3: not built\n");
    return;
  }
  char script[4200];
  snprintf(script, sizeof script, "%s/tests/data/python/add.py", g_src);
  Opened o;
  if (open_fw(&o, "python3", script, NULL, NULL)) return;
  CHECK(model_info(&o) == 0, "python3: getModelInfo");
  CHECK(o.prop.input_meta.num_tensors == 2 && o.prop.output_meta.num_tensors == 2,
        "python3: 2 in, 2 out");
  GstTensorFilterFrameworkInfo info;
  memset(&info, 0, sizeof info);
  CHECK(o.fw->getFrameworkInfo(o.fw, &o.prop, o.priv, &info) == 0, "python3: info");
  float a[4] = {1, 2, 3, 4}, b[4] = {10, 20, 30, 40}, s[4] = {0}, p[4] = {0};
  GstTensorMemory im[2] = {{a, 16}, {b, 16}}, om[2] = {{s, 16}, {p, 16}};
  if (info.allocate_in_invoke) om[0].data = om[1].data = NULL;
  CHECK(o.fw->invoke(o.fw, &o.prop, o.priv, im, om) == 0, "python3: invoke");
  const float *rs = om[0].data, *rp = om[1].data;
  CHECK(rs && rp && rs[0] == 11 && rs[3] == 44 && rp[1] == 40 && rp[2] == 90,
        "python3: values (allocate_in_invoke=%d)", info.allocate_in_invoke);
  for (int i = 0; info.allocate_in_invoke && i < 2; ++i) {
    GstTensorFilterFrameworkEventData ev;
    memset(&ev, 0, sizeof ev);
    ev.data = om[i].data;
    CHECK(o.fw->eventHandler(o.fw, &o.prop, o.priv, DESTROY_NOTIFY, &ev) == 0,
          "python3: DESTROY_NOTIFY");
  }
  close_fw(&o, 1);
  printf("ok python3 (add.py)\n");
}

static void case_lua(void) {
  if (!have_backend("lua")) {
    printf("skip lua: not built\n");
    return;
  }
  char path[] = "/tmp/nns_find_lua_XXXXXX";
  int fd = mkstemp(path);
  CHECK(fd >= 0, "mkstemp");
  const char *text =
      "inputTensorsInfo = { num = 1, dim = {{4, 1}}, type = {'float32'} }\n"
      "outputTensorsInfo = { num = 1, dim = {{4, 1}}, type = {'uint8'} }\n"
      "function nnstreamer_invoke()\n"
      "  local x, y = input_tensor(1), output_tensor(1)\n"
      "  for i = 1, #x do y[i] = 2 * x[i] + 1 end\n"
      "end\n";
  CHECK(write(fd, text, strlen(text)) == (ssize_t)strlen(text), "write script");
  close(fd);
  Opened o;
  if (open_fw(&o, "lua", path, NULL, NULL)) {
    unlink(path);
    return;
  }
  int info_rc = model_info(&o);
  float x[4] = {0.f, 1.75f, -3.f, 500.f};
  uint8_t y[4] = {0};
  GstTensorMemory im = {x, 16}, om = {y, 4};
  int rc = o.fw->invoke(o.fw, &o.prop, o.priv, &im, &om);
  close_fw(&o, 1);
  unlink(path);
  CHECK(info_rc == 0, "lua: getModelInfo");
  CHECK(rc == 0, "lua: invoke");
  CHECK(y[0] == 1 && y[1] == 4 && y[2] == 0 && y[3] == 255, "lua: values %u %u %u %u", y[0], y[1],
        y[2], y[3]);
  printf("ok lua\n");
}

/* ---- names that are not frameworks; decoders and converters -------------------------- */

static void case_lookups(void) {
  CHECK(nnstreamer_filter_find("no-such-framework") == NULL, "unknown name gives NULL");
  CHECK(nnstreamer_filter_find(NULL) == NULL, "NULL gives NULL");
  const GstTensorDecoderDef *dec = nnstreamer_decoder_find("direct_video");
  CHECK(dec && dec->modename && strcmp(dec->modename, "direct_video") == 0 && dec->decode,
        "nnstreamer_decoder_find(direct_video)");
  CHECK(nnstreamer_decoder_find("direct_video") == dec, "same decoder table");
  CHECK(nnstreamer_decoder_find("no_such_decoder") == NULL, "unknown decoder");
  const NNStreamerExternalConverter *conv = nnstreamer_converter_find("python3");
  if (have_backend("python3")) {
    /* The python3 converter is built with the python3 filter. */
    CHECK(conv && conv->convert && strcmp(conv->name, "python3") == 0,
          "nnstreamer_converter_find(python3)");
  }
  CHECK(nnstreamer_converter_find("no_such_converter") == NULL, "unknown converter");
  printf("ok lookups\n");
}

int main(int argc, char **argv) {
  if (argc < 4) {
    fprintf(stderr, "usage: %s <models dir> <source dir> <test filter dir>\n", argv[0]);
    return 2;
  }
  gst_init(NULL, NULL);
  g_models = argv[1];
  g_src = argv[2];
  g_filters = argv[3];
  int have_models = file_exists(g_models, "models/add.tflite");
  case_custom_easy();
  case_custom();
  if (have_models) {
    case_onnxruntime();
    case_pytorch();
    case_add_tflite("armnn");
    case_add_tflite("tensorflow-lite");
    case_add_tflite("tensorflow2-lite");
    case_opencv();
  } else {
    printf("skip onnxruntime, pytorch, armnn, opencv: %s has no models\n", g_models);
  }
  case_python3();
  case_lua();
  case_lookups();
  printf(g_failed ? "FAILED\n" : "OK\n");
  return g_failed ? 1 : 0;
}
