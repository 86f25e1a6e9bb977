// SPDX-License-Identifier: LGPL-2.1-only
// libnnstreamer-decoder-util.so: the helpers NNStreamer's decoder sub-plugins link (ext_util.h).
#include <cstring>

#include "compat/compat_export.h"
#include "compat/ext_util.h"
#include "nnstreamer_log.h"

// NNStreamer's `rasters`: the label glyphs of characters 32..126, 13 rows of 8 pixels, row 0 at
// the bottom (NNStreamer's own bounding-box decoder reads them through initSingleLineSprite()).
// Made from the bounding_boxes decoder's public-domain 8x13 font (top row first) when that
// table is in the tree; without it the symbol is left out (docs/compat-nnstreamer-2x.md).
#if __has_include("decoder/bounding_boxes/font_8x13.h")
#include "decoder/bounding_boxes/font_8x13.h"

// Same layout as uint8_t[95][13], filled at compile time; exported under the C name `rasters`.
struct NnsCompatRasters {
  uint8_t rows[95][13];
  constexpr NnsCompatRasters() : rows{} {
    for (int c = 0; c < 95; ++c)
      for (int r = 0; r < 13; ++r) rows[c][r] = nns::bbox::kFont8x13[c][12 - r];
  }
};
extern __attribute__((visibility("default")))
const NnsCompatRasters nns_compat_rasters __asm__("rasters");
const NnsCompatRasters nns_compat_rasters;
#endif

NNS_COMPAT_API void _free_labels(imglabel_t *data) {
  if (!data) return;
  if (data->labels) {
    for (guint i = 0; i < data->total_labels; ++i) g_free(data->labels[i]);
    g_free(data->labels);
  }
  data->labels = nullptr;
  data->total_labels = 0;
  data->max_word_length = 0;
}

NNS_COMPAT_API void loadImageLabels(const char *label_path, imglabel_t *l) {
  if (!l) return;
  _free_labels(l);
  gchar *text = nullptr;
  gsize len = 0;
  GError *err = nullptr;
  if (!label_path || !g_file_get_contents(label_path, &text, &len, &err) || len == 0) {
    ml_loge("cannot read label file %s: %s", label_path ? label_path : "(null)",
            err ? err->message : "empty file");
    g_clear_error(&err);
    g_free(text);
    return;
  }
  if (text[len - 1] == '\n') text[len - 1] = '\0';
  gchar **lines = g_strsplit(text, "\n", -1);
  l->total_labels = g_strv_length(lines);
  l->labels = g_new0(char *, l->total_labels);
  for (guint i = 0; i < l->total_labels; ++i) {
    l->labels[i] = g_strdup(lines[i]);
    l->max_word_length = MAX(l->max_word_length, std::strlen(lines[i]));
  }
  g_strfreev(lines);
  g_free(text);
}

NNS_COMPAT_API void initSingleLineSprite(singleLineSprite_t v, rasters_t r, uint32_t pv) {
  for (int c = 0; c < 256; ++c) {
    int glyph = (c >= 32 && c < 127) ? c - 32 : '*' - 32;
    for (int row = 0; row < 13; ++row) {
      uint8_t bits = r[glyph][row];
      for (int x = 0; x < 8; ++x) v[c][12 - row][x] = (bits & (0x80u >> x)) ? pv : 0;
    }
  }
}

NNS_COMPAT_API void setFramerateFromConfig(GstCaps *caps, const GstTensorsConfig *config) {
  if (!caps || !config) return;
  if (config->rate_n >= 0 && config->rate_d > 0)
    gst_caps_set_simple(caps, "framerate", GST_TYPE_FRACTION, config->rate_n, config->rate_d,
                        nullptr);
}
