// SPDX-License-Identifier: LGPL-2.1-only
// Functions of NNStreamer's decoder and converter helper libraries (libnnstreamer-decoder-util.so:
// ext/nnstreamer/tensor_decoder/tensordecutil.h; libnnstreamer-converter-util.so:
// tensor_converter_util.h). NNStreamer does not install these headers; its own decoder and
// converter sub-plugins link the libraries, so compiled ones need the symbols.
#pragma once

#include <glib.h>
#include <gst/gst.h>
#include <stdint.h>

#include "nnstreamer_plugin_api_util.h"
#include "tensor_typedef.h"

G_BEGIN_DECLS

/* 256 characters x 13 rows x 8 pixels, one uint32 pixel value each. */
typedef uint32_t singleLineSprite_t[256][13][8];
/* Glyphs of characters 32..126: 13 rows of 8 pixels (bit 7 = left), row 0 at the bottom. */
typedef uint8_t rasters_t[][13];

typedef struct {
  char **labels;         /* one string per line of the label file, or NULL */
  guint total_labels;    /* number of labels */
  gsize max_word_length; /* length of the longest label */
} imglabel_t;

/* Replaces l's labels with the lines of the file (a last empty line is dropped). */
void loadImageLabels(const char *label_path, imglabel_t *l);
/* Expands the glyphs into v: pixel value pv where the glyph is set, 0 elsewhere; characters
 * outside 32..126 get the glyph of '*'. Row 0 of v is the top row. */
void initSingleLineSprite(singleLineSprite_t v, rasters_t r, uint32_t pv);
/* Frees the labels and zeroes the struct. */
void _free_labels(imglabel_t *data);
/* Sets "framerate" on caps from config when the config has a valid rate. */
void setFramerateFromConfig(GstCaps *caps, const GstTensorsConfig *config);

/* Converter sub-plugins' get_out_config for media whose tensors are only known per buffer: one
 * uint8 tensor 1:1:1:1 and the input's framerate (0/1 when it has none). */
gboolean tcu_get_out_config(const GstCaps *in_cap, GstTensorsConfig *config);

G_END_DECLS
