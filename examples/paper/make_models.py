# SPDX-License-Identifier: LGPL-2.1-only
"""Generates the models of the paper experiments (examples/paper, docs/paper-experiments.md).

Usage: /usr/bin/python3 examples/paper/make_models.py <output folder>

Every model is a small torch module exported to ONNX (opset 13). The weights are NOT trained:
they are random (fixed seed), except for one hand-set "brightness" path in the detectors so that
the cascades find the bright moving blobs of the generated clips (make_inputs.py) and the later
stages have real regions to work on. The figures these models give are about speed and data
flow, not about accuracy.

Written files (all in <output folder>):
  e1_fast.onnx, e1_mid.onnx, e1_slow.onnx   E1: three classifiers of different speeds,
                                            input uint8 NHWC 1x224x224x3
  e2_video.onnx  uint8 1x128x128x3 -> float32 1x16    (per video frame features)
  e2_audio.onnx  int16 1600x1    -> float32 1x32    (per 100 ms audio features)
  e2_gru.onnx    (float32 1x12x16, 1x4x32, 1x40x6) -> float32 1x5 (GRU over the three windows)
  e3_pnet_<i>.onnx  uint8 1x120x160x3 -> boxes 1xNx1x4, logits 1xNx2 at scale i (in-model resize)
  e3_priors.txt     priors of the three scales concatenated (tensor_region / mobilenet-ssd)
  e3_rnet.onnx   4 crops uint8 1xHxWx3 (free H, W) + regions uint32 4x4 ->
                 refined regions int32 4x4, scores 1x4, best 1
  e3_onet.onnx   4 crops + the three R-Net outputs -> boxes int32 4x4, scores 1x4 (times R-Net's),
                 landmarks 4x10, best 1
  e4_ssd_<S>.onnx   uint8 1xSxSx3 -> boxes 1xNx1x4, logits 1xNx3, S = 160 and 320
  e4_priors_<S>.txt
  labels2.txt, labels3.txt
  paper_models.json  facts the C++ program and docs read (sizes, N, thresholds)
"""

import json
import os
import sys

import numpy as np
import onnx
import torch
import torch.nn as nn
import torch.nn.functional as F

OPSET = 13
E3_W, E3_H = 160, 120
E3_SCALES = [(96, 72), (64, 48), (40, 30)]  # scaled (width, height) of the P-Net inputs
E3_K = 4  # candidate regions after NMS


def to_nchw(x):
    """uint8 NHWC -> float32 NCHW in [0, 1]."""
    return x.float().permute(0, 3, 1, 2) / 255.0


def gray(x):
    return x.mean(dim=1, keepdim=True)


def conv_stack(channels, strides):
    layers = []
    for cin, cout, s in zip(channels[:-1], channels[1:], strides):
        layers += [nn.Conv2d(cin, cout, 3, stride=s, padding=1), nn.ReLU()]
    return nn.Sequential(*layers)


class Classifier(nn.Module):
    """E1: a plain CNN classifier whose cost is set by its widths."""

    def __init__(self, channels, strides, classes=10):
        super().__init__()
        self.body = conv_stack(channels, strides)
        self.head = nn.Linear(channels[-1], classes)

    def forward(self, x):
        y = self.body(to_nchw(x))
        return torch.softmax(self.head(y.mean(dim=(2, 3))), dim=1)


class VideoFeat(nn.Module):
    def __init__(self):
        super().__init__()
        self.body = conv_stack([3, 64, 128, 128], [1, 2, 2])
        self.fc = nn.Linear(128, 16)

    def forward(self, x):
        return torch.tanh(self.fc(self.body(to_nchw(x)).mean(dim=(2, 3))))


class AudioFeat(nn.Module):
    def __init__(self):
        super().__init__()
        self.c1 = nn.Conv1d(1, 16, 25, stride=4)
        self.c2 = nn.Conv1d(16, 32, 9, stride=4)
        self.fc = nn.Linear(32, 32)

    def forward(self, x):
        y = (x.float() / 32768.0).reshape(1, 1, -1)  # 1600x1 (NNStreamer 1:1600) -> NCL
        y = F.relu(self.c2(F.relu(self.c1(y))))
        return torch.tanh(self.fc(y.mean(dim=2)))


class Gru(nn.Module):
    """E2: one GRU per stream over its window, the last states joined by a linear layer."""

    def __init__(self):
        super().__init__()
        self.gv = nn.GRU(16, 32, batch_first=True)
        self.ga = nn.GRU(32, 32, batch_first=True)
        self.gs = nn.GRU(6, 16, batch_first=True)
        self.fc = nn.Linear(80, 5)

    def forward(self, v, a, s):
        _, hv = self.gv(v)
        _, ha = self.ga(a)
        _, hs = self.gs(s)
        return torch.softmax(self.fc(torch.cat([hv[0], ha[0], hs[0]], dim=1)), dim=1)


class PNet(nn.Module):
    """E3 first stage at one scale: resize in the model, P-Net-shaped body (receptive field 12,
    stride 2), SSD-shaped outputs. The face logit is the window brightness (hand-set) plus a
    small share of the untrained head."""

    def __init__(self, size):
        super().__init__()
        self.size = size  # (h, w)
        self.c1 = nn.Conv2d(3, 32, 3)
        self.c2 = nn.Conv2d(32, 64, 3)
        self.c3 = nn.Conv2d(64, 64, 3)
        self.cls = nn.Conv2d(64, 2, 1)
        self.reg = nn.Conv2d(64, 4, 1)

    def forward(self, x):
        y = F.interpolate(to_nchw(x), size=self.size, mode="bilinear", align_corners=False)
        bright = F.avg_pool2d(gray(y), 12, stride=2)  # 1x1xGhxGw, same grid as the body
        t = F.relu(self.c1(y))
        t = F.max_pool2d(t, 2, 2, ceil_mode=True)
        t = F.relu(self.c3(F.relu(self.c2(t))))
        logit = 0.05 * self.cls(t)
        face = 12.0 * (bright - 0.45) + logit[:, 1:2]
        logits = torch.cat([-face, face], dim=1)  # background, face
        reg = 0.5 * torch.tanh(self.reg(t))
        n = logits.shape[2] * logits.shape[3]
        return (reg.permute(0, 2, 3, 1).reshape(1, n, 1, 4),
                logits.permute(0, 2, 3, 1).reshape(1, n, 2))


class Refine(nn.Module):
    """E3 R-Net / O-Net: K crops of any size resized to `side` in the model, a small CNN,
    scores (brightness of the crop, hand-set, plus the untrained head) and box refinement."""

    def __init__(self, side, channels, landmarks):
        super().__init__()
        self.side = side
        self.body = conv_stack(channels, [1] + [2] * (len(channels) - 2))
        self.fc = nn.Linear(channels[-1] * (side // 2 ** (len(channels) - 2)) ** 2, 128)
        self.score = nn.Linear(128, 1)
        self.bbr = nn.Linear(128, 4)
        self.landmarks = nn.Linear(128, 10) if landmarks else None

    def forward(self, crops, regions, prev_scores=None, prev_best=None):
        xs = [F.interpolate(to_nchw(c), size=(self.side, self.side), mode="bilinear",
                            align_corners=False) for c in crops]
        x = torch.cat(xs, dim=0)
        h = F.relu(self.fc(self.body(x).flatten(1)))
        bright = gray(x).mean(dim=(1, 2, 3))
        scores = torch.sigmoid(10.0 * (bright - 0.4) + 0.1 * self.score(h)[:, 0])
        if prev_scores is not None:  # O-Net: the cascade's score is the product of the stages
            scores = scores * prev_scores[0] + 0.0 * prev_best
        d = 0.1 * torch.tanh(self.bbr(h))
        r = regions.float()
        nx = torch.clamp(r[:, 0] + d[:, 0] * r[:, 2], 0, E3_W - 1)
        ny = torch.clamp(r[:, 1] + d[:, 1] * r[:, 3], 0, E3_H - 1)
        nw = torch.minimum(torch.clamp(r[:, 2] * (1 + d[:, 2]), min=1.0), E3_W - nx)
        nh = torch.minimum(torch.clamp(r[:, 3] * (1 + d[:, 3]), min=1.0), E3_H - ny)
        boxes = torch.stack([nx, ny, nw, nh], dim=1).to(torch.int32)
        outs = [boxes, scores.unsqueeze(0), scores.max().reshape(1)]
        if self.landmarks is not None:
            outs.insert(2, torch.sigmoid(self.landmarks(h)))
        return tuple(outs)


class Ssd(nn.Module):
    """E4: SSD-shaped detector, two feature maps (strides 16 and 32), 3 priors per cell,
    3 classes (background + 2). Class 1 is the cell brightness (hand-set) plus the head."""

    def __init__(self, side, width):
        super().__init__()
        self.side = side
        w = width
        self.body = conv_stack([3, w, 2 * w, 2 * w, 4 * w, 4 * w], [2, 2, 1, 2, 2])
        self.extra = conv_stack([4 * w, 4 * w], [2])
        self.cls = nn.ModuleList([nn.Conv2d(4 * w, 9, 3, padding=1) for _ in range(2)])
        self.reg = nn.ModuleList([nn.Conv2d(4 * w, 12, 3, padding=1) for _ in range(2)])

    def forward(self, x):
        y = to_nchw(x)
        f1 = self.body(y)
        f2 = self.extra(f1)
        boxes, logits = [], []
        for i, f in enumerate([f1, f2]):
            stride = 16 * 2 ** i
            bright = F.avg_pool2d(gray(y), stride, stride)  # cell brightness
            c = 0.05 * self.cls[i](f)  # 1x9xGhxGw = 3 priors x 3 classes
            c = c + torch.cat([-8.0 * (bright - 0.45), 8.0 * (bright - 0.45),
                               torch.zeros_like(bright) - 2.0] * 3, dim=1)
            r = 0.5 * torch.tanh(self.reg[i](f))
            n = f.shape[2] * f.shape[3] * 3
            logits.append(c.permute(0, 2, 3, 1).reshape(1, n, 3))
            boxes.append(r.permute(0, 2, 3, 1).reshape(1, n, 1, 4))
        return torch.cat(boxes, dim=1), torch.cat(logits, dim=1)


def export(module, inputs, path, in_names, out_names, dynamic=None):
    module.eval()
    with torch.no_grad():
        torch.onnx.export(module, inputs, path, opset_version=OPSET, input_names=in_names,
                          output_names=out_names, dynamic_axes=dynamic)


def regions_as_uint32(path, name):
    """torch has no uint32: make graph input `name` uint32 and cast it to the int32 the
    exported graph uses (tensor_region writes uint32 regions)."""
    m = onnx.load(path)
    g = m.graph
    inner = name + "_i32"
    for node in g.node:
        node.input[:] = [inner if i == name else i for i in node.input]
    g.node.insert(0, onnx.helper.make_node("Cast", [name], [inner], to=onnx.TensorProto.INT32))
    for inp in g.input:
        if inp.name == name:
            inp.type.tensor_type.elem_type = onnx.TensorProto.UINT32
    onnx.checker.check_model(m)
    onnx.save(m, path)


def write_priors(path, rows):
    with open(path, "w") as f:
        for row in rows:  # ycenter, xcenter, h, w
            f.write(" ".join("%.6f" % v for v in row) + "\n")


def pnet_priors():
    rows = [[], [], [], []]
    counts = []
    for (w, h) in E3_SCALES:
        gh, gw = (h - 12) // 2 + 1, (w - 12) // 2 + 1
        counts.append(gh * gw)
        for i in range(gh):
            for j in range(gw):
                rows[0].append((2 * i + 6) / h)
                rows[1].append((2 * j + 6) / w)
                rows[2].append(12.0 / h)
                rows[3].append(12.0 / w)
    return rows, counts


def ssd_priors(side):
    rows = [[], [], [], []]
    for stride, sizes in [(16, [0.1, 0.15, 0.2]), (32, [0.3, 0.45, 0.6])]:
        g = side // stride
        for i in range(g):
            for j in range(g):
                for s in sizes:
                    rows[0].append((i + 0.5) / g)
                    rows[1].append((j + 0.5) / g)
                    rows[2].append(s)
                    rows[3].append(s)
    return rows


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "paper-models"
    os.makedirs(out, exist_ok=True)
    torch.manual_seed(14)
    p = lambda name: os.path.join(out, name)  # noqa: E731
    img224 = torch.zeros(1, 224, 224, 3, dtype=torch.uint8)
    # E1: three speeds (about 1 : 3 : 8; the three in series miss 30 fps on this machine).
    export(Classifier([3, 32, 64, 64], [1, 2, 2]), img224, p("e1_fast.onnx"), ["image"], ["scores"])
    export(Classifier([3, 32, 64, 64, 128, 128], [2, 1, 1, 2, 2]), img224, p("e1_mid.onnx"), ["image"],
           ["scores"])
    export(Classifier([3, 32, 64, 64, 128, 128, 128, 128], [2, 1, 1, 1, 2, 1, 1]), img224,
           p("e1_slow.onnx"), ["image"], ["scores"])
    # E2
    export(VideoFeat(), torch.zeros(1, 128, 128, 3, dtype=torch.uint8), p("e2_video.onnx"),
           ["frame"], ["features"])
    export(AudioFeat(), torch.zeros(1600, 1, dtype=torch.int16), p("e2_audio.onnx"), ["pcm"],
           ["features"])
    export(Gru(), (torch.zeros(1, 12, 16), torch.zeros(1, 4, 32), torch.zeros(1, 40, 6)),
           p("e2_gru.onnx"), ["video", "audio", "imu"], ["activity"])
    # E3
    frame = torch.zeros(1, E3_H, E3_W, 3, dtype=torch.uint8)
    for i, (w, h) in enumerate(E3_SCALES):
        export(PNet((h, w)), frame, p("e3_pnet_%d.onnx" % i), ["frame"], ["boxes", "logits"])
    rows, counts = pnet_priors()
    write_priors(p("e3_priors.txt"), rows)
    crops = [torch.zeros(1, 20 + 3 * k, 24 + 2 * k, 3, dtype=torch.uint8) for k in range(E3_K)]
    names = ["crop%d" % k for k in range(E3_K)]
    dyn = {n: {1: "h%d" % k, 2: "w%d" % k} for k, n in enumerate(names)}
    regions = torch.tensor([[10, 10, 24, 20]] * E3_K, dtype=torch.int32)
    export(Refine(24, [3, 28, 48, 64], False), (crops, regions), p("e3_rnet.onnx"),
           names + ["regions"], ["boxes", "scores", "best"], dyn)
    regions_as_uint32(p("e3_rnet.onnx"), "regions")
    export(Refine(48, [3, 32, 64, 64, 128], True),
           (crops, regions, torch.zeros(1, E3_K), torch.zeros(1)), p("e3_onet.onnx"),
           names + ["regions", "rnet_scores", "rnet_best"], ["boxes", "scores", "landmarks", "best"],
           dyn)
    # E4
    ssd = {}
    for side, width in [(160, 16), (320, 32)]:
        export(Ssd(side, width), torch.zeros(1, side, side, 3, dtype=torch.uint8),
               p("e4_ssd_%d.onnx" % side), ["image"], ["boxes", "logits"])
        rows4 = ssd_priors(side)
        write_priors(p("e4_priors_%d.txt" % side), rows4)
        ssd[str(side)] = len(rows4[0])
    with open(p("labels2.txt"), "w") as f:
        f.write("background\nface\n")
    with open(p("labels3.txt"), "w") as f:
        f.write("background\nblob\nother\n")
    facts = {
        "trained": False,
        "e3": {"width": E3_W, "height": E3_H, "scales": E3_SCALES, "priors": counts,
               "k": E3_K},
        "e4": {"priors": ssd},
    }
    with open(p("paper_models.json"), "w") as f:
        json.dump(facts, f, indent=1)
    print("paper models written to %s" % out)


if __name__ == "__main__":
    main()
