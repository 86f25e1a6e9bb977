/* SPDX-License-Identifier: LGPL-2.1-only */
/* NNStreamer 2.x's single-value helpers (tensor_data.h): a typed element, typecasts with
 * NNStreamer's C-cast rules (float to unsigned goes through the signed type of the same width),
 * and the averages / standard deviations tensor_transform's stand mode uses. Exported by
 * libnnstreamer-single.so and libnnstreamer.so. */
#ifndef NNSTREAMER_TENSOR_DATA_H_
#define NNSTREAMER_TENSOR_DATA_H_

#include <glib.h>

#include "tensor_typedef.h"

G_BEGIN_DECLS

typedef struct {
  tensor_type type;
  tensor_element data;
} tensor_data_s;

/* td = *value read as `type`. FALSE for a NULL argument or an unknown type. */
extern gboolean gst_tensor_data_set(tensor_data_s *td, tensor_type type, gpointer value);
/* *value = td's value, td->type's size. */
extern gboolean gst_tensor_data_get(tensor_data_s *td, gpointer value);
/* Converts td to `type` in place. */
extern gboolean gst_tensor_data_typecast(tensor_data_s *td, tensor_type type);
/* *output (out_type) = *input (in_type) converted. */
extern gboolean gst_tensor_data_raw_typecast(gpointer input, tensor_type in_type, gpointer output,
                                             tensor_type out_type);
/* *result: a g_malloc'ed double, the average of length bytes of `type` elements. */
extern gboolean gst_tensor_data_raw_average(gpointer raw, gsize length, tensor_type type,
                                            gdouble **result);
/* *results: dim[0] averages, one per innermost index (channel). */
extern gboolean gst_tensor_data_raw_average_per_channel(gpointer raw, gsize length,
                                                        tensor_type type, tensor_dim dim,
                                                        gdouble **results);
/* *result: the standard deviation around *average (1e-10 when it is 0). */
extern gboolean gst_tensor_data_raw_std(gpointer raw, gsize length, tensor_type type,
                                        gdouble *average, gdouble **result);
extern gboolean gst_tensor_data_raw_std_per_channel(gpointer raw, gsize length, tensor_type type,
                                                    tensor_dim dim, gdouble *averages,
                                                    gdouble **results);

G_END_DECLS

#endif /* NNSTREAMER_TENSOR_DATA_H_ */
