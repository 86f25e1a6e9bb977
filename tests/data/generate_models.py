# SPDX-License-Identifier: LGPL-2.1-only
"""Generates the tiny test models and their reference outputs (no network access).

Usage: /usr/bin/python3 tests/data/generate_models.py <output folder>

For every model NAME it writes
  NAME.onnx          ONNX (opset 13), static shapes unless the name says "dynamic"
  NAME.pt            TorchScript (torch.jit.trace) of the same module, same inputs/outputs
  NAME.py            an nnstreamer python3 filter script computing the same thing with numpy
  NAME.tflite        TensorFlow Lite twin written with tflite_writer.py (python3-flatbuffers,
                     no TensorFlow); without flatbuffers the sidecar's "not_written" says why
  NAME.in<i>.raw     reference input i (little-endian, C order)
  NAME.out<i>.raw    reference output i computed by torch in float32
  NAME.json          sidecar: names, types, shapes (outermost first, as the frameworks see
                     them) and NNStreamer dims (innermost first), file names, tolerance
and models.json listing every model. See tests/data/README.md.
"""

import json
import os
import sys

import numpy as np
import torch
import torch.nn as nn

try:
    import tflite_writer  # next to this script; needs python3-flatbuffers
    TFLITE_MISSING = None
except ImportError as err:
    tflite_writer = None
    TFLITE_MISSING = ("not written: %s under %s when the models were generated (install Debian's "
                      "python3-flatbuffers, scripts/deps/armnn.apt, remove %%s and rebuild the "
                      "target nns_test_models)" % (err, sys.executable))

TYPE_NAMES = {
    np.dtype(np.float32): "float32",
    np.dtype(np.float64): "float64",
    np.dtype(np.uint8): "uint8",
    np.dtype(np.int8): "int8",
    np.dtype(np.int32): "int32",
    np.dtype(np.int64): "int64",
}


def nns_dims(shape):
    """NNStreamer dims string: innermost first ([1,3,4] -> "4:3:1")."""
    return ":".join(str(d) for d in reversed(shape))


class AddMul(nn.Module):
    """Two inputs, two outputs: (a + b, a * b)."""

    def forward(self, a, b):
        return a + b, a * b


class SubScale(nn.Module):
    """Two inputs, three named outputs that tell the inputs apart: (x - y, x + 2y, x * y)."""

    def forward(self, x, y):
        return x - y, x + 2.0 * y, x * y


class WideLinear(nn.Module):
    """float32 [1,1024] -> [1,1024] through a 1024x1024 matrix: 4 MiB of weights, so that a
    model instance leaked per load stands out in the process's memory."""

    def __init__(self):
        super().__init__()
        self.fc = nn.Linear(1024, 1024, bias=False)

    def forward(self, x):
        return self.fc(x)


class ConvNet(nn.Module):
    """A small NCHW conv net: logits over 5 classes and their softmax."""

    def __init__(self):
        super().__init__()
        self.conv1 = nn.Conv2d(3, 8, 3, padding=1)
        self.conv2 = nn.Conv2d(8, 4, 3, padding=1)
        self.fc = nn.Linear(4 * 4 * 4, 5)

    def forward(self, x):
        y = torch.relu(self.conv1(x))
        y = nn.functional.max_pool2d(y, 2)
        y = torch.relu(self.conv2(y))
        y = nn.functional.max_pool2d(y, 2)
        logits = self.fc(torch.flatten(y, 1))
        return logits, torch.softmax(logits, dim=1)


class Uint8Scale(nn.Module):
    """uint8 NHWC image -> float32 per-pixel channel mean scaled to [0, 1]."""

    def forward(self, x):
        return torch.mean(x.to(torch.float32) * (1.0 / 255.0), dim=3)


# numpy bodies of the python3 filter scripts (same maths as the torch modules).
PY_BODIES = {
    "add_mul": """
    def invoke(self, input_array):
        a = np.asarray(input_array[0], dtype=np.float32).reshape(IN_SHAPES[0])
        b = np.asarray(input_array[1], dtype=np.float32).reshape(IN_SHAPES[1])
        return [np.ascontiguousarray(a + b), np.ascontiguousarray(a * b)]
""",
    "sub_scale": """
    def invoke(self, input_array):
        x = np.asarray(input_array[0], dtype=np.float32).reshape(IN_SHAPES[0])
        y = np.asarray(input_array[1], dtype=np.float32).reshape(IN_SHAPES[1])
        return [np.ascontiguousarray(x - y), np.ascontiguousarray(x + np.float32(2.0) * y),
                np.ascontiguousarray(x * y)]
""",
    "uint8_scale": """
    def invoke(self, input_array):
        x = np.asarray(input_array[0], dtype=np.uint8).reshape(IN_SHAPES[0])
        y = (x.astype(np.float32) * np.float32(1.0 / 255.0)).mean(axis=3, dtype=np.float32)
        return [np.ascontiguousarray(y.astype(np.float32))]
""",
    "conv_net": """
    def _conv(self, x, w, b):
        n, c, h, wd = x.shape
        p = np.pad(x, ((0, 0), (0, 0), (1, 1), (1, 1)))
        cols = np.stack([p[:, :, i:i + h, j:j + wd] for i in range(3) for j in range(3)], axis=2)
        # cols: n, c, 9, h, w ; w: o, c, 3, 3
        y = np.einsum("nckhw,ock->nohw", cols, w.reshape(w.shape[0], c, 9))
        return y + b.reshape(1, -1, 1, 1)

    @staticmethod
    def _pool(x):
        n, c, h, w = x.shape
        return x.reshape(n, c, h // 2, 2, w // 2, 2).max(axis=(3, 5))

    def invoke(self, input_array):
        x = np.asarray(input_array[0], dtype=np.float32).reshape(IN_SHAPES[0])
        y = self._pool(np.maximum(self._conv(x, W["conv1.weight"], W["conv1.bias"]), 0))
        y = self._pool(np.maximum(self._conv(y, W["conv2.weight"], W["conv2.bias"]), 0))
        z = (y.reshape(y.shape[0], -1) @ W["fc.weight"].T + W["fc.bias"]).astype(np.float32)
        e = np.exp(z - z.max(axis=1, keepdims=True))
        p = (e / e.sum(axis=1, keepdims=True)).astype(np.float32)
        return [np.ascontiguousarray(z), np.ascontiguousarray(p)]
""",
}


def write_py_filter(out_dir, name, module, inputs, outputs):
    weights = ""
    if name == "conv_net":
        items = []
        for k, v in module.state_dict().items():
            arr = v.detach().numpy().astype(np.float32)
            items.append(
                "    %r: np.array(%s, dtype=np.float32).reshape(%r),"
                % (k, repr(arr.ravel().tolist()), tuple(arr.shape))
            )
        weights = "W = {\n" + "\n".join(items) + "\n}\n"
    in_shapes = [list(a.shape) for a in inputs]
    lines = [
        "# SPDX-License-Identifier: LGPL-2.1-only",
        "# Generated by tests/data/generate_models.py: python3 filter twin of %s.onnx" % name,
        "import numpy as np",
        "import nnstreamer_python as nns",
        "",
        "IN_SHAPES = %r" % (in_shapes,),
        weights,
        "",
        "class CustomFilter(object):",
        "    def __init__(self, *args):",
        "        self.input_dims = [%s]"
        % ", ".join(
            "nns.TensorShape(%r, np.%s)" % (list(reversed(a.shape)), a.dtype.name) for a in inputs
        ),
        "        self.output_dims = [%s]"
        % ", ".join(
            "nns.TensorShape(%r, np.%s)" % (list(reversed(o.shape)), o.dtype.name)
            for o in outputs
        ),
        "",
        "    def getInputDim(self):",
        "        return self.input_dims",
        "",
        "    def getOutputDim(self):",
        "        return self.output_dims",
        PY_BODIES[name],
    ]
    with open(os.path.join(out_dir, name + ".py"), "w") as f:
        f.write("\n".join(lines))


def tensor_entry(prefix, i, name, arr, out_dir, model):
    fname = "%s.%s%d.raw" % (model, prefix, i)
    arr = np.ascontiguousarray(arr)
    arr.astype(arr.dtype.newbyteorder("<")).tofile(os.path.join(out_dir, fname))
    return {
        "name": name,
        "type": TYPE_NAMES[arr.dtype],
        "shape": list(arr.shape),
        "dims": nns_dims(arr.shape),
        "file": fname,
    }


def export(out_dir, name, module, inputs, in_names, out_names, description, dynamic=None,
           tolerance=1e-5, make_pt=True, make_py=True, make_tflite=True):
    module.eval()
    tin = tuple(torch.from_numpy(a) for a in inputs)
    with torch.no_grad():
        touts = module(*tin)
    if isinstance(touts, torch.Tensor):
        touts = (touts,)
    outputs = [t.detach().numpy() for t in touts]

    onnx_path = os.path.join(out_dir, name + ".onnx")
    torch.onnx.export(
        module, tin, onnx_path, opset_version=13, input_names=in_names,
        output_names=out_names, dynamic_axes=dynamic, do_constant_folding=True)
    if make_pt:
        with torch.no_grad():
            traced = torch.jit.trace(module, tin)
        traced.save(os.path.join(out_dir, name + ".pt"))
    if make_py:
        write_py_filter(out_dir, name, module, inputs, outputs)
    not_written = {}
    if make_tflite and tflite_writer:
        if not tflite_writer.write(os.path.join(out_dir, name + ".tflite"), name, module, inputs,
                                   in_names, out_names, description):
            sys.exit("generate_models.py: no TFLite twin of %s in tflite_writer.py" % name)
    elif make_tflite:
        not_written["tflite"] = TFLITE_MISSING % os.path.join(out_dir, "models.json")

    sidecar = {
        "model": name,
        "description": description,
        "files": {"onnx": name + ".onnx"},
        "inputs": [tensor_entry("in", i, n, a, out_dir, name)
                   for i, (n, a) in enumerate(zip(in_names, inputs))],
        "outputs": [tensor_entry("out", i, n, o, out_dir, name)
                    for i, (n, o) in enumerate(zip(out_names, outputs))],
        "tolerance": {"abs": tolerance, "rel": 1e-4},
    }
    if make_pt:
        sidecar["files"]["pytorch"] = name + ".pt"
    if make_py:
        sidecar["files"]["python3"] = name + ".py"
    if make_tflite and tflite_writer:
        sidecar["files"]["tflite"] = name + ".tflite"
    if not_written:
        sidecar["not_written"] = not_written
    if dynamic:
        sidecar["dynamic_axes"] = {k: list(v) for k, v in dynamic.items()}
    with open(os.path.join(out_dir, name + ".json"), "w") as f:
        json.dump(sidecar, f, indent=1)
    return sidecar


DARKNET_CFG = """[net]
batch=1
width=8
height=6
channels=3

[convolutional]
filters=4
size=3
stride=1
pad=1
activation=leaky

[maxpool]
size=2
stride=2

[connected]
output=5
activation=linear
"""


def write_darknet(out_dir, rng):
    """tiny_darknet.cfg + .weights for OpenCV's Darknet reader: conv3x3 (4 filters, pad 1, leaky
    0.1) -> maxpool 2x2 -> connected 5, on float32 NCHW [1,3,6,8] (height 6, width 8: not square,
    so a swapped height/width shows). The reference is numpy."""
    name = "tiny_darknet"
    conv_w = rng.uniform(-0.5, 0.5, (4, 3, 3, 3)).astype(np.float32)
    conv_b = rng.uniform(-0.1, 0.1, 4).astype(np.float32)
    h, w = 6, 8
    fc_w = rng.uniform(-0.3, 0.3, (5, 4 * (h // 2) * (w // 2))).astype(np.float32)
    fc_b = rng.uniform(-0.1, 0.1, 5).astype(np.float32)
    x = rng.uniform(-1, 1, (1, 3, h, w)).astype(np.float32)

    p = np.pad(x[0], ((0, 0), (1, 1), (1, 1)))
    y = np.zeros((4, h, w), np.float32)
    for i in range(3):
        for j in range(3):
            y += np.einsum("oc,chw->ohw", conv_w[:, :, i, j], p[:, i:i + h, j:j + w])
    y += conv_b[:, None, None]
    y = np.where(y > 0, y, np.float32(0.1) * y)
    y = y.reshape(4, h // 2, 2, w // 2, 2).max(axis=(2, 4))
    out = (fc_w @ y.reshape(-1) + fc_b).astype(np.float32).reshape(1, 5)

    with open(os.path.join(out_dir, name + ".cfg"), "w") as f:
        f.write(DARKNET_CFG)
    with open(os.path.join(out_dir, name + ".weights"), "wb") as f:
        # Header: major, minor, revision (int32), images seen (uint64 from version 0.2 on);
        # then per layer biases followed by weights (conv: filters x channels x size x size,
        # connected: outputs x inputs), little-endian float32.
        np.array([0, 2, 5], "<i4").tofile(f)
        np.array([0], "<u8").tofile(f)
        for arr in (conv_b, conv_w, fc_b, fc_w):
            arr.astype("<f4").tofile(f)
    sidecar = {
        "model": name,
        "description": "Darknet cfg+weights: float32 NCHW [1,3,6,8] -> conv3x3(4, leaky) -> "
                       "maxpool2 -> connected [1,5]; numpy reference",
        "files": {"darknet_cfg": name + ".cfg", "darknet_weights": name + ".weights"},
        "inputs": [tensor_entry("in", 0, "data", x, out_dir, name)],
        "outputs": [tensor_entry("out", 0, "fullyConnected_2", out, out_dir, name)],
        "tolerance": {"abs": 1e-5, "rel": 0.0},
    }
    with open(os.path.join(out_dir, name + ".json"), "w") as f:
        json.dump(sidecar, f, indent=1)
    return sidecar


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: generate_models.py <output folder>")
    out_dir = sys.argv[1]
    os.makedirs(out_dir, exist_ok=True)
    torch.manual_seed(0)
    rng = np.random.RandomState(1234)
    models = []

    a = rng.uniform(-2, 2, (1, 3, 4)).astype(np.float32)
    b = rng.uniform(-2, 2, (1, 3, 4)).astype(np.float32)
    models.append(export(out_dir, "add_mul", AddMul(), [a, b], ["a", "b"], ["sum", "product"],
                         "two float32 inputs [1,3,4] -> (a+b, a*b)"))

    x = rng.uniform(-1, 1, (1, 3, 16, 16)).astype(np.float32)
    models.append(export(out_dir, "conv_net", ConvNet(), [x], ["image"],
                         ["logits", "probs"],
                         "float32 NCHW [1,3,16,16] -> 2x(conv3x3+relu+maxpool) -> fc: "
                         "logits [1,5] and their softmax [1,5]"))

    u = rng.randint(0, 256, (1, 8, 8, 3)).astype(np.uint8)
    models.append(export(out_dir, "uint8_scale", Uint8Scale(), [u], ["pixels"], ["mean"],
                         "uint8 NHWC [1,8,8,3] -> float32 channel mean / 255 [1,8,8]"))

    # Same maths as add_mul with a free batch axis: for dynamic-shape tests (ONNX only).
    dyn = {"a": {0: "batch"}, "b": {0: "batch"}, "sum": {0: "batch"}, "product": {0: "batch"}}
    models.append(export(out_dir, "add_mul_dynamic", AddMul(), [a, b], ["a", "b"],
                         ["sum", "product"], "add_mul with a dynamic batch axis", dynamic=dyn,
                         make_pt=False, make_py=False, make_tflite=False))

    models.append(write_darknet(out_dir, rng))

    # Outputs and inputs picked by name (tensor_filter inputname=/outputname=). Drawn last so
    # the other models keep their reference data.
    sx = rng.uniform(-2, 2, (1, 2, 3)).astype(np.float32)
    sy = rng.uniform(-2, 2, (1, 2, 3)).astype(np.float32)
    models.append(export(out_dir, "sub_scale", SubScale(), [sx, sy], ["x", "y"],
                         ["diff", "wsum", "prod"],
                         "two float32 inputs [1,2,3] -> (x-y, x+2y, x*y), named outputs",
                         make_tflite=False))

    # Big enough (4 MiB of weights) for the load/unload leak tests (tests/slow/).
    w = rng.uniform(-1, 1, (1, 1024)).astype(np.float32)
    models.append(export(out_dir, "wide_linear", WideLinear(), [w], ["input"], ["output"],
                         "float32 [1,1024] -> linear 1024x1024 without bias -> [1,1024]",
                         tolerance=1e-4, make_py=False, make_tflite=False))

    with open(os.path.join(out_dir, "models.json"), "w") as f:
        json.dump({"models": [m["model"] for m in models]}, f, indent=1)


if __name__ == "__main__":
    main()
