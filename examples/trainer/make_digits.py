#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-only
"""Makes the on-device training demo's data and model in OUT_DIR:
  train.dat/.json  data repository (NNStreamer's format): 1497 samples of the 8x8 handwritten
                   digits of scikit-learn's load_digits, each an input tensor float32 64:1
                   (pixels / 16) and a label tensor float32 10:1 (one-hot); the first 1200 are
                   for training, the other 297 for validation
  test.dat/.json   the 300 held-apart digits, input tensor only; test_labels.u8 their classes
  digits_mlp.pt    an untrained TorchScript MLP 64 -> 64 -> 10 (random weights, seed 3)
  config.json      tensor_trainer's model-config for the pytorch trainer (SGD, momentum 0.9,
                   learning rate 0.05, batch 16, cross entropy)
usage: make_digits.py OUT_DIR
"""
import json
import os
import sys

import numpy as np
import torch
from sklearn.datasets import load_digits

out = sys.argv[1]
os.makedirs(out, exist_ok=True)
digits = load_digits()
x = (digits.data / 16.0).astype(np.float32)  # 1797 x 64
y = digits.target.astype(np.int64)
order = np.random.RandomState(0).permutation(len(x))
x, y = x[order], y[order]
n_test = 300
train_x, train_y = x[:-n_test], y[:-n_test]
test_x, test_y = x[-n_test:], y[-n_test:]


def write_repo(name, samples, caps):
    data = b"".join(samples)
    with open(os.path.join(out, name + ".dat"), "wb") as f:
        f.write(data)
    meta = {"gst_caps": caps, "total_samples": len(samples), "sample_size": len(samples[0])}
    with open(os.path.join(out, name + ".json"), "w") as f:
        json.dump(meta, f, indent=2)


onehot = np.eye(10, dtype=np.float32)
write_repo("train", [train_x[i].tobytes() + onehot[train_y[i]].tobytes()
                     for i in range(len(train_x))],
           "other/tensors, format=(string)static, framerate=(fraction)0/1, num_tensors=(int)2, "
           "dimensions=(string)64:1.10:1, types=(string)float32.float32")
write_repo("test", [test_x[i].tobytes() for i in range(len(test_x))],
           "other/tensors, format=(string)static, framerate=(fraction)0/1, num_tensors=(int)1, "
           "dimensions=(string)64:1, types=(string)float32")
test_y.astype(np.uint8).tofile(os.path.join(out, "test_labels.u8"))


class Mlp(torch.nn.Module):
    def __init__(self):
        super().__init__()
        self.hidden = torch.nn.Linear(64, 64)
        self.out = torch.nn.Linear(64, 10)

    def forward(self, x):
        return self.out(torch.relu(self.hidden(x)))


torch.manual_seed(3)
torch.jit.script(Mlp()).save(os.path.join(out, "digits_mlp.pt"))
with open(os.path.join(out, "config.json"), "w") as f:
    json.dump({"model": "digits_mlp.pt", "loss": "cross_entropy", "optimizer": "sgd",
               "learning_rate": 0.05, "momentum": 0.9, "batch_size": 16, "seed": 1}, f, indent=2)
print("train: %d samples (1200 training + %d validation), test: %d" %
      (len(train_x), len(train_x) - 1200, len(test_x)))
