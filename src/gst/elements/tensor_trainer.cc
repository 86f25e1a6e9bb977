// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_trainer
 *
 * Trains a model on the samples of a tensor stream with a trainer sub-plugin (`framework`,
 * NNStreamer's GstTensorTrainerFramework: nnstreamer_plugin_api_trainer.h; ours is
 * `pytorch`). Each buffer is one sample: its first `num-inputs` tensors are inputs, the next
 * `num-labels` labels. Per epoch the sub-plugin gets `num-training-samples` training samples
 * then `num-validation-samples` validation samples; `epochs` epochs in all. When training ends
 * the sub-plugin saves the model to `model-save-path` (optionally starting from
 * `model-load-path`).
 *
 * Output (as NNStreamer): one float64 tensor 1:1:4:1 = training loss, training accuracy,
 * validation loss, validation accuracy (a value the sub-plugin reports as <= 0 is -inf), pushed
 * after the first sample of each epoch and when each epoch completes. At the end of training
 * an element message "nnstreamer-trainer-complete" carries the final figures and the model path.
 *
 *   gst-launch-1.0 datareposrc location=train.dat json=train.json epochs=5 ! \
 *     tensor_trainer framework=pytorch model-config=mlp.json model-save-path=mlp.pt \
 *     num-inputs=1 num-labels=1 num-training-samples=1000 num-validation-samples=200 \
 *     epochs=5 ! tensor_sink
 */
#include <gst/gst.h>

#include <cmath>
#include <condition_variable>
#include <cstring>
#include <mutex>
#include <sys/stat.h>

#include "core/c_tensor_info.h"
#include "core/meta_header.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"
#include "gst/trainer/trainer_registry.h"
#include "nnstreamer_plugin_api_trainer.h"

GST_DEBUG_CATEGORY_STATIC(tensor_trainer_debug);
#define GST_CAT_DEFAULT tensor_trainer_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_TRAINER (gst_tensor_trainer_get_type())
G_DECLARE_FINAL_TYPE(GstTensorTrainer, gst_tensor_trainer, GST, TENSOR_TRAINER, GstElement)
G_END_DECLS

namespace {

using nns::ErrorKind;
using nns::fail;

struct Settings {
  std::string framework, model_config, model_save_path, model_load_path;
  guint num_inputs = 1, num_labels = 1, num_training = 0, num_validation = 0, epochs = 1;
};

struct TrainerPriv {
  std::mutex lock;  // settings; the flags below (with cond)
  std::condition_variable cond;
  Settings s;
  bool epoch_done = false, training_done = false, flushing = false;
  // streaming thread
  const GstTensorTrainerFramework *fw = nullptr;
  void *fw_data = nullptr;
  bool created = false, completion_posted = false;
  GstTensorTrainerProperties prop{};
  std::string config_s, save_s, load_s;  // storage of prop's strings
  GstTensorTrainerEventNotifier notifier{};
  nns::TensorsConfig in_config;
  uint64_t epoch_samples = 0, total_samples = 0;
  // Per-sample scratch, kept so the streaming path allocates nothing per buffer.
  std::vector<GstMemory *> mems;
  std::vector<GstMapInfo> maps;
};

enum {
  PROP_0,
  PROP_FRAMEWORK,
  PROP_MODEL_CONFIG,
  PROP_MODEL_SAVE_PATH,
  PROP_MODEL_LOAD_PATH,
  PROP_NUM_INPUTS,
  PROP_NUM_LABELS,
  PROP_NUM_TRAINING,
  PROP_NUM_VALIDATION,
  PROP_EPOCHS
};

}  // namespace

struct _GstTensorTrainer {
  GstElement parent;
  GstPad *sinkpad, *srcpad;
  TrainerPriv *priv;
};

G_DEFINE_TYPE(GstTensorTrainer, gst_tensor_trainer, GST_TYPE_ELEMENT)
GST_ELEMENT_REGISTER_DEFINE(tensor_trainer, "tensor_trainer", GST_RANK_NONE,
                            GST_TYPE_TENSOR_TRAINER)

static GstStaticPadTemplate sink_template = GST_STATIC_PAD_TEMPLATE(
    "sink", GST_PAD_SINK, GST_PAD_ALWAYS,
    GST_STATIC_CAPS("other/tensors, format = (string) { static, flexible }, "
                    "framerate = (fraction) [ 0, max ]"));
static GstStaticPadTemplate src_template = GST_STATIC_PAD_TEMPLATE(
    "src", GST_PAD_SRC, GST_PAD_ALWAYS,
    GST_STATIC_CAPS("other/tensors, format = (string) static, framerate = (fraction) [ 0, max ]"));

static void gst_tensor_trainer_set_property(GObject *object, guint id, const GValue *value,
                                            GParamSpec *pspec) {
  auto *p = GST_TENSOR_TRAINER(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  auto str = [&](std::string &f) {
    const gchar *v = g_value_get_string(value);
    f = v ? v : "";
  };
  switch (id) {
    case PROP_FRAMEWORK:
      str(p->s.framework);
      break;
    case PROP_MODEL_CONFIG:
      str(p->s.model_config);
      break;
    case PROP_MODEL_SAVE_PATH:
      str(p->s.model_save_path);
      break;
    case PROP_MODEL_LOAD_PATH:
      str(p->s.model_load_path);
      break;
    case PROP_NUM_INPUTS:
      p->s.num_inputs = g_value_get_uint(value);
      break;
    case PROP_NUM_LABELS:
      p->s.num_labels = g_value_get_uint(value);
      break;
    case PROP_NUM_TRAINING:
      p->s.num_training = g_value_get_uint(value);
      break;
    case PROP_NUM_VALIDATION:
      p->s.num_validation = g_value_get_uint(value);
      break;
    case PROP_EPOCHS:
      p->s.epochs = g_value_get_uint(value);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_trainer_get_property(GObject *object, guint id, GValue *value,
                                            GParamSpec *pspec) {
  auto *p = GST_TENSOR_TRAINER(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  switch (id) {
    case PROP_FRAMEWORK:
      g_value_set_string(value, p->s.framework.c_str());
      break;
    case PROP_MODEL_CONFIG:
      g_value_set_string(value, p->s.model_config.c_str());
      break;
    case PROP_MODEL_SAVE_PATH:
      g_value_set_string(value, p->s.model_save_path.c_str());
      break;
    case PROP_MODEL_LOAD_PATH:
      g_value_set_string(value,
                         p->s.model_load_path.empty() ? nullptr : p->s.model_load_path.c_str());
      break;
    case PROP_NUM_INPUTS:
      g_value_set_uint(value, p->s.num_inputs);
      break;
    case PROP_NUM_LABELS:
      g_value_set_uint(value, p->s.num_labels);
      break;
    case PROP_NUM_TRAINING:
      g_value_set_uint(value, p->s.num_training);
      break;
    case PROP_NUM_VALIDATION:
      g_value_set_uint(value, p->s.num_validation);
      break;
    case PROP_EPOCHS:
      g_value_set_uint(value, p->s.epochs);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

// " (<the sub-plugin's reason>)", or a pointer to its log when it gives none.
static std::string why(const GstTensorTrainerFramework *fw) {
  std::string e = nns::gst::TrainerRegistry::instance().last_error(fw);
  return e.empty() ? " (see its log)" : ": " + e;
}

// Creates and starts the sub-plugin for the negotiated inputs. Throws naming what is wrong.
static void create_framework(GstTensorTrainer *self) {
  auto *p = self->priv;
  Settings s;
  {
    std::lock_guard<std::mutex> l(p->lock);
    s = p->s;
  }
  if (s.framework.empty()) fail(ErrorKind::kSettings, "framework is not set (e.g. pytorch)");
  if (s.model_config.empty())
    fail(ErrorKind::kSettings, "model-config is not set (the model configuration file)");
  struct stat st {};
  if (::stat(s.model_config.c_str(), &st) != 0 || !S_ISREG(st.st_mode))
    fail(ErrorKind::kNotFound, "model-config " + s.model_config + " is not a readable file");
  if (s.model_save_path.empty())
    fail(ErrorKind::kSettings, "model-save-path is not set (where the trained model goes)");
  if (s.epochs == 0 || s.num_inputs == 0 || s.num_labels == 0)
    fail(ErrorKind::kSettings, "epochs, num-inputs and num-labels must be at least 1 (got " +
                                   std::to_string(s.epochs) + ", " + std::to_string(s.num_inputs) +
                                   ", " + std::to_string(s.num_labels) + ")");
  if (s.num_training + s.num_validation == 0)
    fail(ErrorKind::kSettings, "num-training-samples + num-validation-samples is 0");
  const std::size_t n = p->in_config.info.size();
  if (p->in_config.info.format == nns::TensorFormat::kStatic && s.num_inputs + s.num_labels != n)
    fail(ErrorKind::kNegotiation,
         "a sample has " + std::to_string(n) + " tensors but num-inputs + num-labels = " +
             std::to_string(s.num_inputs) + " + " + std::to_string(s.num_labels));
  auto &reg = nns::gst::TrainerRegistry::instance();
  p->fw = reg.find(s.framework);
  if (!p->fw) {
    std::string why = reg.load_error(s.framework);
    fail(ErrorKind::kNotFound, "framework '" + s.framework + "' is not a trainer sub-plugin" +
                                   (why.empty() ? "" : " (" + why + ")") +
                                   "; available: " + nns::join(reg.names(), ", "));
  }
  p->config_s = s.model_config;
  p->save_s = s.model_save_path;
  p->load_s = s.model_load_path;
  nns::gst_info_clear(&p->prop.input_meta);
  nns::to_c(p->in_config.info, &p->prop.input_meta);
  p->prop.model_config = p->config_s.c_str();
  p->prop.model_save_path = p->save_s.c_str();
  p->prop.model_load_path = p->load_s.empty() ? nullptr : p->load_s.c_str();
  p->prop.num_inputs = s.num_inputs;
  p->prop.num_labels = s.num_labels;
  p->prop.num_training_samples = s.num_training;
  p->prop.num_validation_samples = s.num_validation;
  p->prop.num_epochs = s.epochs;
  p->prop.epoch_count = 0;
  if (p->fw->create(p->fw, &p->prop, &p->fw_data) < 0)
    fail(ErrorKind::kLibrary, "trainer '" + s.framework + "' could not create the model from " +
                                  s.model_config + why(p->fw));
  p->created = true;
  p->notifier.version = GST_TENSOR_TRAINER_FRAMEWORK_V1;
  p->notifier.notifier = self;
  if (p->fw->start(p->fw, &p->prop, &p->notifier, p->fw_data) != 0)
    fail(ErrorKind::kLibrary,
         "trainer '" + s.framework + "' could not start training" + why(p->fw));
}

static void destroy_framework(GstTensorTrainer *self) {
  auto *p = self->priv;
  if (p->created) {
    bool done;
    {
      std::lock_guard<std::mutex> l(p->lock);
      done = p->training_done;
    }
    if (!done && p->fw->stop) p->fw->stop(p->fw, &p->prop, &p->fw_data);
    p->fw->destroy(p->fw, &p->prop, &p->fw_data);
  }
  p->created = false;
  p->fw = nullptr;
  p->fw_data = nullptr;
  nns::gst_info_clear(&p->prop.input_meta);
  std::lock_guard<std::mutex> l(p->lock);
  p->epoch_done = p->training_done = false;
  p->completion_posted = false;
  p->epoch_samples = p->total_samples = 0;
}

// Waits until `flag` is set by the sub-plugin; false when flushing ended the wait.
static bool wait_for(TrainerPriv *p, bool TrainerPriv::*flag) {
  std::unique_lock<std::mutex> l(p->lock);
  p->cond.wait(l, [&] { return p->*flag || p->flushing; });
  if (p->flushing) return false;
  if (flag == &TrainerPriv::epoch_done) p->epoch_done = false;
  return true;
}

static double stat_or_inf(double v) {
  return v > 0 ? v : -INFINITY;
}

static GstBuffer *stats_buffer(GstTensorTrainer *self, GstClockTime pts) {
  auto *p = self->priv;
  if (p->fw->getStatus(p->fw, &p->prop, p->fw_data) < 0)
    fail(ErrorKind::kLibrary, "trainer could not report its status" + why(p->fw));
  const double v[4] = {stat_or_inf(p->prop.training_loss), stat_or_inf(p->prop.training_accuracy),
                       stat_or_inf(p->prop.validation_loss),
                       stat_or_inf(p->prop.validation_accuracy)};
  GstBuffer *buf = gst_buffer_new_allocate(nullptr, sizeof v, nullptr);
  gst_buffer_fill(buf, 0, v, sizeof v);
  GST_BUFFER_PTS(buf) = pts;
  GST_LOG_OBJECT(self, "epoch %u/%u: loss %f acc %f val_loss %f val_acc %f", p->prop.epoch_count,
                 p->prop.num_epochs, v[0], v[1], v[2], v[3]);
  return buf;
}

static void post_completion(GstTensorTrainer *self) {
  auto *p = self->priv;
  if (p->completion_posted) return;
  p->completion_posted = true;
  p->fw->getStatus(p->fw, &p->prop, p->fw_data);
  GstStructure *s = gst_structure_new(
      "nnstreamer-trainer-complete", "epochs", G_TYPE_UINT, p->prop.epoch_count, "training-loss",
      G_TYPE_DOUBLE, p->prop.training_loss, "training-accuracy", G_TYPE_DOUBLE,
      p->prop.training_accuracy, "validation-loss", G_TYPE_DOUBLE, p->prop.validation_loss,
      "validation-accuracy", G_TYPE_DOUBLE, p->prop.validation_accuracy, "model-save-path",
      G_TYPE_STRING, p->save_s.c_str(), nullptr);
  gst_element_post_message(GST_ELEMENT(self), gst_message_new_element(GST_OBJECT(self), s));
}

static GstFlowReturn trainer_chain(GstPad *, GstObject *parent, GstBuffer *inbuf) {
  auto *self = GST_TENSOR_TRAINER(parent);
  auto *p = self->priv;
  nns::gst::BufferPtr in(inbuf);
  return nns::gst::guard(self, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    if (!p->created) create_framework(self);
    {
      std::lock_guard<std::mutex> l(p->lock);
      if (p->training_done) {
        GST_WARNING_OBJECT(self, "training is complete; sample dropped");
        return GST_FLOW_OK;
      }
    }
    const bool flexible = p->in_config.info.format != nns::TensorFormat::kStatic;
    const std::size_t n = nns::gst::buffer_tensor_count(inbuf);
    const std::size_t want = p->prop.num_inputs + p->prop.num_labels;
    if (n != want)
      fail(ErrorKind::kStream, "sample " + std::to_string(p->total_samples) + " has " +
                                   std::to_string(n) + " tensors, expected num-inputs + " +
                                   "num-labels = " + std::to_string(want));
    GstTensorMemory tensors[NNS_TENSOR_SIZE_LIMIT];
    nns::TensorsInfo sample_info;  // flexible: this sample's tensors, from their headers
    p->mems.assign(n, nullptr);
    p->maps.resize(n);
    std::size_t mapped = 0;
    struct Unmap {  // releases what was mapped, however the loop ends
      TrainerPriv *p;
      std::size_t *mapped;
      ~Unmap() {
        for (std::size_t i = 0; i < *mapped; ++i) gst_memory_unmap(p->mems[i], &p->maps[i]);
        for (GstMemory *m : p->mems)
          if (m) gst_memory_unref(m);
      }
    } unmap{p, &mapped};
    for (std::size_t i = 0; i < n; ++i) {
      p->mems[i] = nns::gst::buffer_get_tensor(inbuf, i);
      if (!p->mems[i] || !gst_memory_map(p->mems[i], &p->maps[i], GST_MAP_READ))
        fail(ErrorKind::kStream, "cannot map tensor " + std::to_string(i) + " of sample " +
                                     std::to_string(p->total_samples));
      ++mapped;
      const uint8_t *data = p->maps[i].data;
      std::size_t size = p->maps[i].size;
      std::size_t expected;
      if (flexible) {
        nns::MetaHeader h = nns::parse_meta_header(data, size);
        data += nns::kMetaHeaderSize;
        size -= nns::kMetaHeaderSize;
        expected = h.info().byte_size();
        sample_info.tensors.push_back(h.info());
      } else {
        expected = p->in_config.info[i].byte_size();
      }
      if (size != expected)
        fail(ErrorKind::kStream, "sample " + std::to_string(p->total_samples) + ", tensor " +
                                     std::to_string(i) + ": " + std::to_string(size) +
                                     " bytes, expected " + std::to_string(expected));
      tensors[i].data = const_cast<uint8_t *>(data);
      tensors[i].size = size;
    }
    if (flexible) {  // the sub-plugin sees each sample's shapes in input_meta
      nns::gst_info_clear(&p->prop.input_meta);
      nns::to_c(sample_info, &p->prop.input_meta);
    }
    if (p->fw->push_data(p->fw, &p->prop, p->fw_data, tensors) < 0)
      fail(ErrorKind::kLibrary,
           "trainer refused sample " + std::to_string(p->total_samples) + why(p->fw));
    ++p->epoch_samples;
    ++p->total_samples;
    const GstClockTime pts = GST_BUFFER_PTS(inbuf);
    const uint64_t per_epoch =
        static_cast<uint64_t>(p->prop.num_training_samples) + p->prop.num_validation_samples;
    GstBuffer *out = nullptr;
    if (p->epoch_samples == per_epoch) {
      if (!wait_for(p, &TrainerPriv::epoch_done)) return GST_FLOW_FLUSHING;
      p->epoch_samples = 0;
      out = stats_buffer(self, pts);
      bool done;
      {
        std::lock_guard<std::mutex> l(p->lock);
        done = p->training_done;
      }
      if (done) post_completion(self);
    } else if (p->epoch_samples == 1) {
      out = stats_buffer(self, pts);
    }
    return out ? gst_pad_push(self->srcpad, out) : GST_FLOW_OK;
  });
}

static gboolean trainer_sink_event(GstPad *pad, GstObject *parent, GstEvent *event) {
  auto *self = GST_TENSOR_TRAINER(parent);
  auto *p = self->priv;
  switch (GST_EVENT_TYPE(event)) {
    case GST_EVENT_CAPS: {
      GstCaps *caps;
      gst_event_parse_caps(event, &caps);
      gboolean ok = nns::gst::guard(self, FALSE, [&]() -> gboolean {
        p->in_config = nns::gst::config_from_caps(caps);
        nns::TensorsConfig out;
        nns::TensorInfo t;
        t.type = nns::TensorType::kFloat64;
        t.dims = nns::make_dims({1, 1, 4, 1});
        out.info.tensors.push_back(t);
        out.rate_n = p->in_config.rate_n < 0 ? 0 : p->in_config.rate_n;
        out.rate_d = p->in_config.rate_d <= 0 ? 1 : p->in_config.rate_d;
        nns::gst::CapsPtr oc(gst_caps_new_full(nns::gst::structure_from_config(out), nullptr));
        return gst_pad_set_caps(self->srcpad, oc.get());
      });
      gst_event_unref(event);
      return ok;
    }
    case GST_EVENT_EOS: {
      bool done;
      {
        std::lock_guard<std::mutex> l(p->lock);
        done = p->training_done;
      }
      if (!done && p->created) {
        const uint64_t total =
            (static_cast<uint64_t>(p->prop.num_training_samples) + p->prop.num_validation_samples) *
            p->prop.num_epochs;
        if (p->total_samples < total) {
          NNS_POST_ERROR(self, ErrorKind::kStream,
                         "end of stream after " + std::to_string(p->total_samples) + " of " +
                             std::to_string(total) +
                             " samples ((num-training-samples + num-validation-samples) x "
                             "epochs); training did not finish and " +
                             p->save_s + " was not written");
        } else if (wait_for(p, &TrainerPriv::training_done)) {
          post_completion(self);
        }
      } else if (!p->created) {
        NNS_POST_ERROR(self, ErrorKind::kStream,
                       "end of stream before any sample: nothing was trained");
      }
      break;
    }
    case GST_EVENT_FLUSH_START: {
      std::lock_guard<std::mutex> l(p->lock);
      p->flushing = true;
      p->cond.notify_all();
      break;
    }
    case GST_EVENT_FLUSH_STOP: {
      std::lock_guard<std::mutex> l(p->lock);
      p->flushing = false;
      break;
    }
    default:
      break;
  }
  return gst_pad_event_default(pad, parent, event);
}

static GstStateChangeReturn trainer_change_state(GstElement *element, GstStateChange t) {
  auto *self = GST_TENSOR_TRAINER(element);
  auto *p = self->priv;
  if (t == GST_STATE_CHANGE_PAUSED_TO_READY) {
    std::lock_guard<std::mutex> l(p->lock);
    p->flushing = true;  // a streaming thread waiting for the sub-plugin lets go
    p->cond.notify_all();
  } else if (t == GST_STATE_CHANGE_READY_TO_PAUSED) {
    std::lock_guard<std::mutex> l(p->lock);
    p->flushing = false;
  }
  GstStateChangeReturn ret =
      GST_ELEMENT_CLASS(gst_tensor_trainer_parent_class)->change_state(element, t);
  if (t == GST_STATE_CHANGE_PAUSED_TO_READY) destroy_framework(self);
  return ret;
}

extern "C" void nnstreamer_trainer_notify_event(GstTensorTrainerEventNotifier *notifier,
                                                GstTensorTrainerEventType type, void *) {
  if (!notifier || !notifier->notifier || !GST_IS_TENSOR_TRAINER(notifier->notifier)) return;
  auto *p = GST_TENSOR_TRAINER(notifier->notifier)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  if (type == TRAINER_EVENT_EPOCH_COMPLETION)
    p->epoch_done = true;
  else if (type == TRAINER_EVENT_TRAINING_COMPLETION)
    p->training_done = true;
  else
    return;
  p->cond.notify_all();
}

static void gst_tensor_trainer_finalize(GObject *object) {
  auto *self = GST_TENSOR_TRAINER(object);
  destroy_framework(self);
  delete self->priv;
  G_OBJECT_CLASS(gst_tensor_trainer_parent_class)->finalize(object);
}

static void gst_tensor_trainer_class_init(GstTensorTrainerClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_trainer_debug, "tensor_trainer", 0, "tensor_trainer");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  gobject_class->set_property = gst_tensor_trainer_set_property;
  gobject_class->get_property = gst_tensor_trainer_get_property;
  gobject_class->finalize = gst_tensor_trainer_finalize;
  auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS |
                                     GST_PARAM_MUTABLE_READY);
  g_object_class_install_property(
      gobject_class, PROP_FRAMEWORK,
      g_param_spec_string("framework", "Framework",
                          "Neural network framework to be used for model training", "", rw));
  g_object_class_install_property(
      gobject_class, PROP_MODEL_CONFIG,
      g_param_spec_string("model-config", "Model configuration file path",
                          "Model configuration file is used to configure the model to be "
                          "trained in neural network framework, set the file path",
                          "", rw));
  g_object_class_install_property(
      gobject_class, PROP_MODEL_SAVE_PATH,
      g_param_spec_string("model-save-path", "Model save path",
                          "Path to save the trained model in framework, if model-config "
                          "contains information about the save file, it is ignored",
                          "", rw));
  g_object_class_install_property(
      gobject_class, PROP_MODEL_LOAD_PATH,
      g_param_spec_string("model-load-path", "Model load path",
                          "Path to a model file to be loaded for the given training session.",
                          nullptr, rw));
  g_object_class_install_property(
      gobject_class, PROP_NUM_INPUTS,
      g_param_spec_uint("num-inputs", "Number of inputs",
                        "An input in a tensor can have one or more features data,set how many "
                        "inputs are received",
                        0, NNS_TENSOR_SIZE_LIMIT, 1, rw));
  g_object_class_install_property(
      gobject_class, PROP_NUM_LABELS,
      g_param_spec_uint("num-labels", "Number of labels",
                        "A label in a tensor can have one or more classes data,set how many "
                        "labels are received",
                        0, NNS_TENSOR_SIZE_LIMIT, 1, rw));
  g_object_class_install_property(
      gobject_class, PROP_NUM_TRAINING,
      g_param_spec_uint("num-training-samples", "Number of training samples",
                        "A sample can consist of multiple inputs and labels in tensors of a "
                        "gstbuffer, set how many samples are taken for training model",
                        0, G_MAXINT, 0, rw));
  g_object_class_install_property(
      gobject_class, PROP_NUM_VALIDATION,
      g_param_spec_uint("num-validation-samples", "Number of validation samples",
                        "A sample can consist of multiple inputs and labels in tensors of a "
                        "gstbuffer, set how many samples are taken for validation model",
                        0, G_MAXINT, 0, rw));
  g_object_class_install_property(
      gobject_class, PROP_EPOCHS,
      g_param_spec_uint("epochs", "Number of epoch",
                        "Epochs are repetitions of training samples and validation samples, "
                        "number of samples received for model training is "
                        "(num-training-samples+num-validation-samples)*epochs",
                        0, G_MAXINT, 1, rw));
  gst_element_class_set_static_metadata(element_class, "TensorTrainer", "Trainer/Tensor",
                                        "Train tensor data using NN Frameworks", "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &sink_template);
  gst_element_class_add_static_pad_template(element_class, &src_template);
  element_class->change_state = trainer_change_state;
}

static void gst_tensor_trainer_init(GstTensorTrainer *self) {
  self->priv = new TrainerPriv();
  nns::gst_info_init(&self->priv->prop.input_meta);
  self->sinkpad = gst_pad_new_from_static_template(&sink_template, "sink");
  gst_pad_set_chain_function(self->sinkpad, trainer_chain);
  gst_pad_set_event_function(self->sinkpad, trainer_sink_event);
  gst_element_add_pad(GST_ELEMENT(self), self->sinkpad);
  self->srcpad = gst_pad_new_from_static_template(&src_template, "src");
  gst_pad_use_fixed_caps(self->srcpad);
  gst_element_add_pad(GST_ELEMENT(self), self->srcpad);
}
