/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * tensor_trainer sub-plugin interface, binary-compatible with NNStreamer 2.x's
 * nnstreamer_plugin_api_trainer.h: the same structs, field order, version word and exported
 * functions, so a trainer sub-plugin built for NNStreamer (libnnstreamer_trainer_<name>.so in a
 * `trainers=` folder) loads into nnstreamer-cpp, and ours into NNStreamer.
 *
 * A sub-plugin registers its table from a constructor with nnstreamer_trainer_probe(); the
 * element calls create() when the first caps arrive (after the properties are set), start()
 * when training begins, push_data() once per sample (inputs then labels, in buffer order),
 * getStatus() to read the current figures into `prop`, stop() to abandon training, destroy() at
 * the end. The sub-plugin reports the end of every epoch and of the whole training through
 * nnstreamer_trainer_notify_event() with the notifier start() received.
 */
#ifndef NNSTREAMER_CPP_PLUGIN_API_TRAINER_H_
#define NNSTREAMER_CPP_PLUGIN_API_TRAINER_H_

#include <stdint.h>

#include "tensor_typedef.h"

/* | 32 bits: validity | 16 bits: API version | 16 bits: the sub-plugin's own | */
#define GST_TENSOR_TRAINER_FRAMEWORK_BASE (0xDEAFDEAD00000000ULL)
#define GST_TENSOR_TRAINER_FRAMEWORK_V1 (GST_TENSOR_TRAINER_FRAMEWORK_BASE | 0x10000ULL)

#ifdef __cplusplus
extern "C" {
#endif

/* What tensor_trainer tells its sub-plugin; the statistics at the end are filled by
 * getStatus(). */
typedef struct _GstTensorTrainerProperties {
  GstTensorsInfo input_meta;   /* the tensors of one sample, as negotiated */
  const char *model_config;    /* `model-config` */
  const char *model_save_path; /* `model-save-path` */
  const char *model_load_path; /* `model-load-path` (NULL when unset) */
  unsigned int num_inputs;     /* the first num_inputs tensors of a sample are inputs */
  unsigned int num_labels;     /* the next num_labels are labels */
  unsigned int num_training_samples;
  unsigned int num_validation_samples;
  unsigned int num_epochs; /* (training + validation samples) x epochs samples arrive */

  unsigned int epoch_count; /* epochs completed */
  double training_loss;
  double training_accuracy;
  double validation_loss;
  double validation_accuracy;
} GstTensorTrainerProperties;

typedef struct _GstTensorTrainerFrameworkInfo {
  const char *name; /* the `framework` property value that selects this sub-plugin */
} GstTensorTrainerFrameworkInfo;

typedef enum {
  TRAINER_EVENT_EPOCH_COMPLETION,    /* one epoch (training + validation) is done */
  TRAINER_EVENT_TRAINING_COMPLETION, /* every epoch is done and the model is saved */
  TRAINER_EVENT_UNKNOWN,
} GstTensorTrainerEventType;

typedef struct _GstTensorTrainerEventNotifier {
  uint64_t version;
  void *notifier; /* the element; pass the struct back to nnstreamer_trainer_notify_event() */
} GstTensorTrainerEventNotifier;

typedef struct _GstTensorTrainerFramework GstTensorTrainerFramework;

/* Every callback returns 0 on success, < 0 on failure. */
struct _GstTensorTrainerFramework {
  uint64_t version; /* GST_TENSOR_TRAINER_FRAMEWORK_V1 */
  int (*create)(const GstTensorTrainerFramework *self, const GstTensorTrainerProperties *prop,
                void **private_data);
  int (*destroy)(const GstTensorTrainerFramework *self, const GstTensorTrainerProperties *prop,
                 void **private_data);
  int (*start)(const GstTensorTrainerFramework *self, const GstTensorTrainerProperties *prop,
               GstTensorTrainerEventNotifier *notifier, void *private_data);
  int (*stop)(const GstTensorTrainerFramework *self, const GstTensorTrainerProperties *prop,
              void **private_data);
  int (*push_data)(const GstTensorTrainerFramework *self, const GstTensorTrainerProperties *prop,
                   void *private_data, const GstTensorMemory *input);
  int (*getStatus)(const GstTensorTrainerFramework *self, GstTensorTrainerProperties *prop,
                   void *private_data);
  /* Mandatory; private_data is NULL when called before create(). */
  int (*getFrameworkInfo)(const GstTensorTrainerFramework *self,
                          const GstTensorTrainerProperties *prop, void *private_data,
                          GstTensorTrainerFrameworkInfo *fw_info);
};

/* Registers a sub-plugin (TRUE on success). The table must outlive its registration. */
extern int nnstreamer_trainer_probe(GstTensorTrainerFramework *ttsp);
/* Unregisters it (TRUE on success). */
extern int nnstreamer_trainer_exit(GstTensorTrainerFramework *ttsp);
/* Called by a sub-plugin, from any thread, to report an epoch or the training as complete. */
extern void nnstreamer_trainer_notify_event(GstTensorTrainerEventNotifier *notifier,
                                            GstTensorTrainerEventType type, void *data);

#ifdef __cplusplus
}
#endif

#endif /* NNSTREAMER_CPP_PLUGIN_API_TRAINER_H_ */
