/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * Test trainer sub-plugin "counting", written in C against the NNStreamer 2.x trainer ABI
 * (nnstreamer_plugin_api_trainer.h only). It learns nothing: its figures are exact functions of
 * what it receives, so tensor_trainer's protocol can be checked value by value.
 *   training_loss      = mean of the first float of the training inputs of the last epoch
 *   training_accuracy  = number of training samples of the last epoch
 *   validation_loss    = mean of the first float of the validation inputs of the last epoch
 *   validation_accuracy= epochs completed
 * model-config: a text file; if it contains "async" the completion events are sent from a
 * thread of its own 50 ms later; if it contains "fail-create", create() fails.
 * At the end it writes "<samples> samples, <epochs> epochs\n" to model-save-path.
 */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "nnstreamer_plugin_api_trainer.h"

int nnstreamer_trainer_probe(GstTensorTrainerFramework *ttsp) __attribute__((weak));
int nnstreamer_trainer_exit(GstTensorTrainerFramework *ttsp) __attribute__((weak));
void nnstreamer_trainer_notify_event(GstTensorTrainerEventNotifier *notifier,
                                     GstTensorTrainerEventType type, void *data)
    __attribute__((weak));

typedef struct {
  int async;
  unsigned in_epoch, epochs, total;
  double sum_train, sum_valid, last[4];
  GstTensorTrainerEventNotifier *notifier;
  pthread_t thread;
  int thread_running;
  char save[1024];
} Counting;

static const char *g_error = "";

static int c_info(const GstTensorTrainerFramework *self, const GstTensorTrainerProperties *prop,
                  void *priv, GstTensorTrainerFrameworkInfo *info) {
  (void)self;
  (void)prop;
  (void)priv;
  info->name = "counting";
  return 0;
}

static int c_create(const GstTensorTrainerFramework *self, const GstTensorTrainerProperties *prop,
                    void **priv) {
  (void)self;
  char text[256] = {0};
  FILE *f = fopen(prop->model_config, "r");
  if (f) {
    size_t n = fread(text, 1, sizeof text - 1, f);
    text[n] = 0;
    fclose(f);
  }
  if (strstr(text, "fail-create")) {
    g_error = "the model config asks create() to fail";
    return -1;
  }
  Counting *c = calloc(1, sizeof *c);
  c->async = strstr(text, "async") != NULL;
  snprintf(c->save, sizeof c->save, "%s", prop->model_save_path ? prop->model_save_path : "");
  *priv = c;
  return 0;
}

static int c_destroy(const GstTensorTrainerFramework *self, const GstTensorTrainerProperties *prop,
                     void **priv) {
  (void)self;
  (void)prop;
  Counting *c = *priv;
  if (c && c->thread_running) pthread_join(c->thread, NULL);
  free(c);
  *priv = NULL;
  return 0;
}

static int c_start(const GstTensorTrainerFramework *self, const GstTensorTrainerProperties *prop,
                   GstTensorTrainerEventNotifier *notifier, void *priv) {
  (void)self;
  (void)prop;
  ((Counting *)priv)->notifier = notifier;
  return 0;
}

static int c_stop(const GstTensorTrainerFramework *self, const GstTensorTrainerProperties *prop,
                  void **priv) {
  (void)self;
  (void)prop;
  (void)priv;
  return 0;
}

typedef struct {
  Counting *c;
  int finished;
} Late;

static void *late_events(void *arg) {
  Late *l = arg;
  struct timespec ts = {0, 50 * 1000 * 1000};
  nanosleep(&ts, NULL);
  nnstreamer_trainer_notify_event(l->c->notifier, TRAINER_EVENT_EPOCH_COMPLETION, NULL);
  if (l->finished)
    nnstreamer_trainer_notify_event(l->c->notifier, TRAINER_EVENT_TRAINING_COMPLETION, NULL);
  free(l);
  return NULL;
}

static int c_push(const GstTensorTrainerFramework *self, const GstTensorTrainerProperties *prop,
                  void *priv, const GstTensorMemory *input) {
  (void)self;
  Counting *c = priv;
  float first;
  if (input[0].size < sizeof first) {
    g_error = "input tensor 0 is smaller than one float";
    return -1;
  }
  memcpy(&first, input[0].data, sizeof first);
  if (c->in_epoch < prop->num_training_samples)
    c->sum_train += first;
  else
    c->sum_valid += first;
  c->total++;
  if (++c->in_epoch < prop->num_training_samples + prop->num_validation_samples) return 0;
  c->epochs++;
  c->last[0] = prop->num_training_samples ? c->sum_train / prop->num_training_samples : 0;
  c->last[1] = prop->num_training_samples;
  c->last[2] = prop->num_validation_samples ? c->sum_valid / prop->num_validation_samples : 0;
  c->last[3] = c->epochs;
  c->sum_train = c->sum_valid = 0;
  c->in_epoch = 0;
  int finished = c->epochs == prop->num_epochs;
  if (finished) {
    FILE *f = fopen(c->save, "w");
    if (f) {
      fprintf(f, "%u samples, %u epochs\n", c->total, c->epochs);
      fclose(f);
    }
  }
  if (c->async) {
    if (c->thread_running) pthread_join(c->thread, NULL);
    Late *l = malloc(sizeof *l);
    l->c = c;
    l->finished = finished;
    c->thread_running = pthread_create(&c->thread, NULL, late_events, l) == 0;
  } else {
    nnstreamer_trainer_notify_event(c->notifier, TRAINER_EVENT_EPOCH_COMPLETION, NULL);
    if (finished)
      nnstreamer_trainer_notify_event(c->notifier, TRAINER_EVENT_TRAINING_COMPLETION, NULL);
  }
  return 0;
}

static int c_status(const GstTensorTrainerFramework *self, GstTensorTrainerProperties *prop,
                    void *priv) {
  (void)self;
  Counting *c = priv;
  prop->epoch_count = c->epochs;
  prop->training_loss = c->last[0];
  prop->training_accuracy = c->last[1];
  prop->validation_loss = c->last[2];
  prop->validation_accuracy = c->last[3];
  return 0;
}

static GstTensorTrainerFramework g_counting = {GST_TENSOR_TRAINER_FRAMEWORK_V1,
                                               c_create,
                                               c_destroy,
                                               c_start,
                                               c_stop,
                                               c_push,
                                               c_status,
                                               c_info};

const char *nns_trainer_subplugin_last_error(void) {
  return g_error;
}

__attribute__((constructor)) static void c_register(void) {
  if (nnstreamer_trainer_probe) nnstreamer_trainer_probe(&g_counting);
}

__attribute__((destructor)) static void c_unregister(void) {
  if (nnstreamer_trainer_exit) nnstreamer_trainer_exit(&g_counting);
}
