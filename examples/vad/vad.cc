// SPDX-License-Identifier: LGPL-2.1-only
/**
 * nns-vad: voice activity detection with Silero VAD (ONNX) in an NNStreamer pipeline whose
 * recurrent state goes round through tensor_reposink/tensor_reposrc. Prints the speech segments
 * (and with --frames every 32 ms frame's speech probability).
 *
 *   filesrc location=AUDIO ! wavparse ! audioconvert ! audioresample !
 *   audio/x-raw,format=S16LE,rate=16000,channels=1 ! tee name=pcm
 *   pcm. ! queue ! tensor_converter frames-per-tensor=64 !
 *   tensor_aggregator frames-in=64 frames-out=576 frames-flush=512 frames-dim=1 !
 *   tensor_transform mode=arithmetic option=typecast:float32,div:32768.0 !
 *   tensor_transform mode=dimchg option=0:1 ! mux.sink_0
 *   tensor_reposrc slot-index=S caps="...dimensions=128:1:2,types=float32..." ! mux.sink_1
 *   tensor_mux name=mux sync-mode=nosync !
 *   tensor_filter framework=onnxruntime model=silero_vad_half.onnx input=576:1,128:1:2
 *     inputtype=float32,float32 ! tensor_demux name=d
 *   d.src_0 ! queue ! appsink name=prob          (speech probability, 1:1 float32)
 *   d.src_1 ! queue ! tensor_reposink slot-index=S   (the next state, 128:1:2 float32)
 *   pcm. ! queue ! appsink name=pcm_out           (only for the signal's reference envelope)
 *
 * Each model call sees 576 samples: the 512 new ones (32 ms at 16 kHz) after the 64 last samples
 * of the previous window, which the Silero v5 ONNX models expect as context; the aggregator's
 * sliding window (576 out, 512 flushed) provides it. --stateless zeroes the state on its way
 * back (tensor_transform mul:0 before tensor_reposink), so every frame starts from scratch: the
 * same pipeline without recurrence, for comparison.
 *
 * Segments follow Silero's own rule: speech starts at a frame with prob >= threshold and ends
 * once prob stays below threshold - 0.15 for --min-silence ms; segments shorter than
 * --min-speech ms are dropped.
 *
 * --sr: the model has a third input `sr`, the sample rate as an int64 scalar (Silero's fp32
 * exports, e.g. silero_vad_16k_op15.onnx): the pipeline tees the window, keeps its first sample
 * (tensor_split tensorpick=0) and turns it into 16000 (typecast:int64,mul:0,add:16000), a
 * constant tensor paced by the audio, muxed in as the third tensor.
 *
 * usage: nns-vad --audio FILE.wav --model silero_vad_half.onnx [--stateless] [--sr] [--frames]
 *                [--threshold 0.5] [--min-speech 250] [--min-silence 100] [--slot 90]
 *                [--custom NumThreads:1]
 * exit:  0 ok, 1 error, 2 usage, 77 a needed element is missing
 */
#include <gst/app/gstappsink.h>
#include <gst/gst.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <string>
#include <vector>

#include "../common/run_to_eos.h"

namespace {

constexpr int kRate = 16000;
constexpr int kWindow = 512;  // new samples per model call (32 ms)
constexpr int kContext = 64;  // samples of the previous window in front of them
constexpr int kStateDim = 128;

struct Args {
  std::string audio, model, custom = "NumThreads:1";
  bool stateless = false, frames = false, sr = false;
  float threshold = 0.5f;
  int min_speech_ms = 250, min_silence_ms = 100;
  unsigned slot = 90;
};

int usage(const char *msg) {
  std::fprintf(
      stderr,
      "nns-vad: %s\nusage: nns-vad --audio FILE.wav --model MODEL.onnx [--stateless] "
      "[--sr] [--frames] [--threshold 0.5] [--min-speech 250] [--min-silence 100] [--slot 90] "
      "[--custom K:V]\n",
      msg);
  return 2;
}

std::string pipeline_desc(const Args &a) {
  const std::string state_caps = "other/tensors,format=static,num_tensors=1,dimensions=(string)" +
                                 std::to_string(kStateDim) +
                                 ":1:2,types=(string)float32,framerate=(fraction)0/1";
  const std::string slot = std::to_string(a.slot);
  const std::string window = std::to_string(kContext + kWindow);
  std::string d = "filesrc location=\"" + a.audio +
                  "\" ! wavparse ! audioconvert ! audioresample ! "
                  "audio/x-raw,format=S16LE,rate=16000,channels=1 ! tee name=pcm "
                  "pcm. ! queue ! tensor_converter frames-per-tensor=" +
                  std::to_string(kContext) +
                  " ! tensor_aggregator frames-in=" + std::to_string(kContext) +
                  " frames-out=" + window + " frames-flush=" + std::to_string(kWindow) +
                  " frames-dim=1 ! "
                  "tensor_transform mode=arithmetic option=typecast:float32,div:32768.0 ! "
                  "tensor_transform mode=dimchg option=0:1 ! ";
  // tensor_mux orders its tensors by the order its pads were linked: audio, state, sr.
  d += a.sr ? "tee name=win win. ! queue ! mux.sink_0 " : "mux.sink_0 ";
  d += "tensor_reposrc slot-index=" + slot + " caps=\"" + state_caps + "\" ! mux.sink_1 ";
  // The sample rate as an int64 scalar per frame, made from the window's first sample.
  if (a.sr)
    d += "win. ! queue ! tensor_split tensorseg=1:1," + std::to_string(kContext + kWindow - 1) +
         ":1 tensorpick=0 ! tensor_transform mode=arithmetic option=typecast:int64,mul:0,add:" +
         std::to_string(kRate) + " ! mux.sink_2 ";
  d += "tensor_mux name=mux sync-mode=nosync ! "
       "tensor_filter framework=onnxruntime model=\"" +
       a.model + "\" input=" + window + ":1," + std::to_string(kStateDim) + ":1:2" +
       (a.sr ? ",1 inputtype=float32,float32,int64 inputname=input,state,sr"
             : " inputtype=float32,float32") +
       " custom=" + a.custom +
       " ! tensor_demux name=d "
       "d.src_0 ! queue ! appsink name=prob sync=false "
       "d.src_1 ! queue ! " +
       (a.stateless ? "tensor_transform mode=arithmetic option=mul:0.0 ! " : "") +
       "tensor_reposink slot-index=" + slot + " pcm. ! queue ! appsink name=pcm_out sync=false";
  return d;
}

struct Collected {
  std::mutex lock;
  std::vector<float> probs;
  std::vector<int16_t> pcm;
  std::string error;
};

GstFlowReturn on_prob(GstAppSink *sink, gpointer data) {
  auto *c = static_cast<Collected *>(data);
  GstSample *s = gst_app_sink_pull_sample(sink);
  if (!s) return GST_FLOW_EOS;
  GstBuffer *b = gst_sample_get_buffer(s);
  float p = NAN;
  if (gst_buffer_get_size(b) == sizeof(float)) gst_buffer_extract(b, 0, &p, sizeof p);
  {
    std::lock_guard g(c->lock);
    if (std::isnan(p) && c->error.empty())
      c->error = "probability buffer of " + std::to_string(gst_buffer_get_size(b)) +
                 " bytes, expected 4 (one float32)";
    c->probs.push_back(p);
  }
  gst_sample_unref(s);
  return GST_FLOW_OK;
}

GstFlowReturn on_pcm(GstAppSink *sink, gpointer data) {
  auto *c = static_cast<Collected *>(data);
  GstSample *s = gst_app_sink_pull_sample(sink);
  if (!s) return GST_FLOW_EOS;
  GstBuffer *b = gst_sample_get_buffer(s);
  std::size_t n = gst_buffer_get_size(b) / sizeof(int16_t);
  {
    std::lock_guard g(c->lock);
    std::size_t at = c->pcm.size();
    c->pcm.resize(at + n);
    gst_buffer_extract(b, 0, c->pcm.data() + at, n * sizeof(int16_t));
  }
  gst_sample_unref(s);
  return GST_FLOW_OK;
}

// Runs the pipeline to EOS; returns "" or the error text.
std::string run(GstElement *pipeline) {
  return nns_example::run_to_eos(pipeline, 120, "timed out after 120 s");
}

// Start time (s) of the 512 new samples of frame k.
double frame_start(std::size_t k) {
  return static_cast<double>(k * kWindow + kContext) / kRate;
}

struct Segment {
  double start, end;
};

std::vector<Segment> segments(const std::vector<float> &probs, const Args &a) {
  const float neg = std::max(a.threshold - 0.15f, 0.01f);
  const double frame_s = static_cast<double>(kWindow) / kRate;
  std::vector<Segment> out;
  bool in_speech = false;
  double start = 0, silence_from = -1;
  auto close = [&](double end) {
    if ((end - start) * 1000 >= a.min_speech_ms) out.push_back({start, end});
    in_speech = false;
    silence_from = -1;
  };
  for (std::size_t k = 0; k < probs.size(); ++k) {
    double t = frame_start(k);
    float p = probs[k];
    if (!in_speech) {
      if (p >= a.threshold) {
        in_speech = true;
        start = t;
        silence_from = -1;
      }
      continue;
    }
    if (p >= a.threshold) {
      silence_from = -1;
    } else if (p < neg) {
      if (silence_from < 0) silence_from = t;
      if ((t + frame_s - silence_from) * 1000 >= a.min_silence_ms) close(silence_from);
    }
  }
  if (in_speech) close(silence_from >= 0 ? silence_from : frame_start(probs.size()));
  return out;
}

bool element_missing(std::string &which) {
  for (const char *name :
       {"tensor_converter", "tensor_aggregator", "tensor_transform", "tensor_mux", "tensor_filter",
        "tensor_demux", "tensor_reposrc", "tensor_reposink", "tensor_split", "wavparse",
        "audioresample", "appsink"}) {
    GstElementFactory *f = gst_element_factory_find(name);
    if (!f) {
      which = name;
      return true;
    }
    gst_object_unref(f);
  }
  return false;
}

}  // namespace

int main(int argc, char **argv) {
  gst_init(&argc, &argv);
  Args a;
  for (int i = 1; i < argc; ++i) {
    std::string k = argv[i];
    auto val = [&]() -> const char * { return i + 1 < argc ? argv[++i] : nullptr; };
    const char *v = nullptr;
    if (k == "--stateless") {
      a.stateless = true;
    } else if (k == "--sr") {
      a.sr = true;
    } else if (k == "--frames") {
      a.frames = true;
    } else if (k == "--audio" || k == "--model" || k == "--custom" || k == "--threshold" ||
               k == "--min-speech" || k == "--min-silence" || k == "--slot") {
      if (!(v = val())) return usage((k + " needs a value").c_str());
      if (k == "--audio") a.audio = v;
      if (k == "--model") a.model = v;
      if (k == "--custom") a.custom = v;
      if (k == "--threshold") a.threshold = std::strtof(v, nullptr);
      if (k == "--min-speech") a.min_speech_ms = std::atoi(v);
      if (k == "--min-silence") a.min_silence_ms = std::atoi(v);
      if (k == "--slot") a.slot = static_cast<unsigned>(std::strtoul(v, nullptr, 10));
    } else {
      return usage(("unknown argument '" + k + "'").c_str());
    }
  }
  if (a.audio.empty() || a.model.empty()) return usage("--audio and --model are required");
  if (!(a.threshold > 0 && a.threshold < 1)) return usage("--threshold must be in (0, 1)");
  std::string missing;
  if (element_missing(missing)) {
    std::fprintf(stderr, "nns-vad: element '%s' not available (GST_PLUGIN_PATH?)\n",
                 missing.c_str());
    return 77;
  }

  std::string desc = pipeline_desc(a);
  GError *e = nullptr;
  GstElement *pipeline = gst_parse_launch(desc.c_str(), &e);
  if (!pipeline || e) {
    std::fprintf(stderr, "nns-vad: cannot build the pipeline: %s\n  %s\n",
                 e ? e->message : "unknown error", desc.c_str());
    if (e) g_error_free(e);
    if (pipeline) gst_object_unref(pipeline);
    return 1;
  }
  Collected c;
  GstAppSinkCallbacks prob_cb{}, pcm_cb{};
  prob_cb.new_sample = on_prob;
  pcm_cb.new_sample = on_pcm;
  GstElement *prob = gst_bin_get_by_name(GST_BIN(pipeline), "prob");
  GstElement *pcm = gst_bin_get_by_name(GST_BIN(pipeline), "pcm_out");
  gst_app_sink_set_callbacks(GST_APP_SINK(prob), &prob_cb, &c, nullptr);
  gst_app_sink_set_callbacks(GST_APP_SINK(pcm), &pcm_cb, &c, nullptr);
  gst_object_unref(prob);
  gst_object_unref(pcm);
  std::string err = run(pipeline);
  gst_object_unref(pipeline);
  if (err.empty()) err = c.error;
  if (!err.empty()) {
    std::fprintf(stderr, "nns-vad: %s\n", err.c_str());
    return 1;
  }

  const double duration = static_cast<double>(c.pcm.size()) / kRate;
  std::printf("audio: %s, %.2f s, %zu frames of 32 ms, state %s\n", a.audio.c_str(), duration,
              c.probs.size(), a.stateless ? "zeroed every frame (--stateless)" : "fed back");
  // Where the waveform itself is not silent (|x| > 1% of full scale): the truth for synthetic
  // speech padded with digital silence, a rough envelope for anything else.
  std::size_t first = c.pcm.size(), last = 0;
  for (std::size_t i = 0; i < c.pcm.size(); ++i)
    if (std::abs(static_cast<int>(c.pcm[i])) > 327) {
      first = std::min(first, i);
      last = i;
    }
  if (first < c.pcm.size()) {
    const double on = static_cast<double>(first) / kRate,
                 off = static_cast<double>(last + 1) / kRate;
    std::printf("signal: above 1%% full scale from %.3f s to %.3f s\n", on, off);
    // Mean probability of the frames inside that span and of those outside it by more than
    // kHangover (the probability decays over a few frames once speech stops).
    constexpr double kHangover = 0.25;
    double in_sum = 0, out_sum = 0, out_max = 0;
    int in_n = 0, out_n = 0;
    for (std::size_t k = 0; k < c.probs.size(); ++k) {
      double s = frame_start(k), e = s + static_cast<double>(kWindow) / kRate;
      if (s >= on && e <= off) {
        in_sum += c.probs[k];
        ++in_n;
      } else if (e <= on - kHangover || s >= off + kHangover) {
        out_sum += c.probs[k];
        out_max = std::max(out_max, static_cast<double>(c.probs[k]));
        ++out_n;
      }
    }
    std::printf(
        "mean prob: %.4f inside the signal span (%d frames), %.4f outside +-0.25 s "
        "(%d frames, max %.4f)\n",
        in_n ? in_sum / in_n : 0.0, in_n, out_n ? out_sum / out_n : 0.0, out_n, out_max);
  }
  if (a.frames)
    for (std::size_t k = 0; k < c.probs.size(); ++k)
      std::printf("frame %zu: %.3f-%.3f s prob %.4f\n", k, frame_start(k),
                  frame_start(k) + static_cast<double>(kWindow) / kRate, c.probs[k]);
  auto segs = segments(c.probs, a);
  for (std::size_t i = 0; i < segs.size(); ++i)
    std::printf("speech %zu: %.3f s - %.3f s\n", i + 1, segs[i].start, segs[i].end);
  std::printf("%zu speech segment(s)\n", segs.size());
  return 0;
}
