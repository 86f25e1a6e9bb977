/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * Decoder sub-plugin API: tensors -> media. The table layout and the function names follow
 * NNStreamer's nnstreamer_plugin_api_decoder.h, so decoders written for NNStreamer can be
 * rebuilt against this header.
 *
 * A decoder lives in libnnstreamer_decoder_<modename>.so in the folders of nnstreamer.ini's
 * [decoder] decoders= key or NNSTREAMER_DECODERS, or is built into the plugin. A .so announces
 * itself in one of two ways:
 *   1. NNStreamer style: a constructor function calls nnstreamer_decoder_probe(&table);
 *   2. it exports  const GstTensorDecoderDef *nns_decoder_subplugin_entry (void);
 *      returning its static table; the host registers it.
 */
#ifndef NNSTREAMER_CPP_PLUGIN_API_DECODER_H_
#define NNSTREAMER_CPP_PLUGIN_API_DECODER_H_

#include <gst/gst.h>

#include "tensor_typedef.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct _GstTensorDecoderDef {
  char *modename; /* the mode= name */
  /* Creates the decoder's private data. Returns TRUE on success. */
  int (*init)(void **private_data);
  /* Frees what init made. */
  void (*exit)(void **private_data);
  /* option1..option9 (opNum 0..8). Returns TRUE when the value is accepted. */
  int (*setOption)(void **private_data, int opNum, const char *param);
  /* Output caps for the given input, or NULL when the input cannot be decoded. The input may
   * not be fixed yet during negotiation. Caller unrefs. */
  GstCaps *(*getOutCaps)(void **private_data, const GstTensorsConfig *config);
  /* Decodes one frame into outbuf (allocated, empty unless getTransformSize gave a size). */
  GstFlowReturn (*decode)(void **private_data, const GstTensorsConfig *config,
                          const GstTensorMemory *input, GstBuffer *outbuf);
  /* Optional: output buffer size for GstBaseTransform::transform_size; NULL or 0 = the decoder
   * appends its own memory in decode. */
  size_t (*getTransformSize)(void **private_data, const GstTensorsConfig *config, GstCaps *caps,
                             size_t size, GstCaps *othercaps, GstPadDirection direction);
} GstTensorDecoderDef;

#define NNS_DECODER_SUBPLUGIN_ENTRY "nns_decoder_subplugin_entry"
typedef const GstTensorDecoderDef *(*nns_decoder_subplugin_entry_fn)(void);

/* Registers a decoder; TRUE when registered, FALSE when invalid or the name is taken. */
extern int nnstreamer_decoder_probe(GstTensorDecoderDef *decoder);
/* Removes the decoder registered as `name`. */
extern void nnstreamer_decoder_exit(const char *name);
/* The decoder registered (or loadable) as `name`, or NULL. */
extern const GstTensorDecoderDef *nnstreamer_decoder_find(const char *name);
/* Describes the decoder's options ("option1", "text", ..., NULL) for gst-inspect and errors. */
extern void nnstreamer_decoder_set_custom_property_desc(const char *name, const char *prop, ...);

#ifdef __cplusplus
}
#endif

#endif /* NNSTREAMER_CPP_PLUGIN_API_DECODER_H_ */
