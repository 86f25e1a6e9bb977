/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * Single-shot inference without a pipeline (NNStreamer's nnstreamer-single.h names and
 * semantics): open a model with a framework, query its input/output, invoke, close.
 * Link with -lnnstreamer-single. Thread safety: one handle may be used from several threads;
 * invokes on one handle are serialized.
 */
#ifndef NNSTREAMER_CPP_SINGLE_H_
#define NNSTREAMER_CPP_SINGLE_H_

#include "ml-api-common.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef void *ml_single_h;

/* model: path(s), ',' separated. input_info/output_info may be NULL when the model knows its
 * shapes; when given they are checked against (or applied to) the model. */
int ml_single_open(ml_single_h *single, const char *model, const ml_tensors_info_h input_info,
                   const ml_tensors_info_h output_info, ml_nnfw_type_e nnfw, ml_nnfw_hw_e hw);
/* As ml_single_open, with tensor_filter's custom= string. */
int ml_single_open_full(ml_single_h *single, const char *model, const ml_tensors_info_h input_info,
                        const ml_tensors_info_h output_info, ml_nnfw_type_e nnfw, ml_nnfw_hw_e hw,
                        const char *custom_option);
/* Keys: "models" (char*), "framework_name" or "framework" (char*, any tensor_filter framework=
 * value; wins over "nnfw"), "input_info"/"output_info" (ml_tensors_info_h), "custom" (char*),
 * "nnfw" (ml_nnfw_type_e*), "hw" (ml_nnfw_hw_e*). Other keys are ignored. */
int ml_single_open_with_option(ml_single_h *single, const ml_option_h option);
int ml_single_close(ml_single_h single);

/* *output is new data the caller destroys. */
int ml_single_invoke(ml_single_h single, const ml_tensors_data_h input, ml_tensors_data_h *output);
/* output was created by the caller from the output info; it is filled in place. */
int ml_single_invoke_fast(ml_single_h single, const ml_tensors_data_h input,
                          ml_tensors_data_h output);
/* Invokes with input shaped as in_info; *output and *out_info (new, the caller destroys both)
 * describe this call's result. Back ends with a dynamic invoke (onnxruntime, pytorch, python3,
 * custom-easy dynamic models) take the shapes per call and report the output's, so models
 * whose output shape depends on the input work; others get in_info through their set-input
 * first (ML_ERROR_NOT_SUPPORTED when they cannot change it; restored when the invoke fails).
 * The handle's input/output info then follow this call. */
int ml_single_invoke_dynamic(ml_single_h single, const ml_tensors_data_h input,
                             const ml_tensors_info_h in_info, ml_tensors_data_h *output,
                             ml_tensors_info_h *out_info);

/* *info is new; the caller destroys it. */
int ml_single_get_input_info(ml_single_h single, ml_tensors_info_h *info);
int ml_single_get_output_info(ml_single_h single, ml_tensors_info_h *info);
/* Changes the input shape when the back end supports it (ML_ERROR_NOT_SUPPORTED otherwise);
 * the output info follows. */
int ml_single_set_input_info(ml_single_h single, const ml_tensors_info_h info);
/* Milliseconds an invoke may take before ML_ERROR_TIMED_OUT (0 = no limit). */
int ml_single_set_timeout(ml_single_h single, unsigned int timeout);
/* tensor_filter property names, values as strings ("3:224:224:1", "uint8,float32", "true"):
 *   input, inputtype, inputname      set: through the back end's set-input (names: metadata)
 *   output, outputtype, outputname   set: outputname; output/outputtype only when the model
 *                                    does not know its output (custom filters)
 *   inputlayout, outputlayout, custom, accelerator
 *                                    set: the model is opened again with the new value
 *   is-updatable ("true"/"false")    set
 *   model                            set: reloads the model; needs is-updatable=true
 *   framework, inputranks, outputranks   read-only
 * Unknown names give ML_ERROR_NOT_SUPPORTED; a bad value ML_ERROR_INVALID_PARAMETER; setting
 * the current value does nothing. *value is a copy the caller frees with free(). */
int ml_single_set_property(ml_single_h single, const char *name, const char *value);
int ml_single_get_property(ml_single_h single, const char *name, char **value);
/* Beyond NNStreamer: the full message of this handle's last error ("" when none). */
const char *ml_single_get_last_error(ml_single_h single);

#ifdef __cplusplus
}
#endif

#endif /* NNSTREAMER_CPP_SINGLE_H_ */
