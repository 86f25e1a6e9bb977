#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-only
"""Makes the multi-sensor demo's inputs in OUT_DIR:
  sys/iio:device0  a fake 3-axis accelerometer (le:s16/16>>0, scale 0.01) at 100 Hz
  sys/iio:device1  a fake light sensor (be:u12/16>>4, scale 0.5) at 10 Hz
  dev/iio:device0, dev/iio:device1  their buffered samples (plain files standing in for the
                   character devices; tensor_src_iio ends the stream at their end)
  e2_gru.pt        a small recurrent model (GRU over 10 accelerometer samples + the light
                   level -> 2 scores), TorchScript; weights are random (seed 7), not trained
  reference.f32    what the pipeline must output: the model run by torch on the values the
                   sensors hold, decoded as tensor_src_iio decodes them (float32 arithmetic)
usage: make_sensors.py OUT_DIR [WINDOWS]
"""
import os
import struct
import sys

import numpy as np
import torch

out = sys.argv[1]
windows = int(sys.argv[2]) if len(sys.argv) > 2 else 5
acc_n = windows * 10  # 10 accelerometer samples per light sample


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text + "\n")


def device(n, name, freq, channels):
    d = os.path.join(out, "sys", "iio:device%d" % n)
    write(os.path.join(d, "name"), name)
    write(os.path.join(d, "sampling_frequency"), str(freq))
    write(os.path.join(d, "sampling_frequency_available"), str(freq))
    write(os.path.join(d, "buffer", "length"), "1")
    write(os.path.join(d, "buffer", "enable"), "0")
    for idx, (ch, typ, scale) in enumerate(channels):
        s = os.path.join(d, "scan_elements")
        write(os.path.join(s, ch + "_en"), "0")
        write(os.path.join(s, ch + "_index"), str(idx))
        write(os.path.join(s, ch + "_type"), typ)
        write(os.path.join(d, ch + "_scale"), scale)


device(0, "e2_accel", 100, [("in_accel_x", "le:s16/16>>0", "0.01"),
                            ("in_accel_y", "le:s16/16>>0", "0.01"),
                            ("in_accel_z", "le:s16/16>>0", "0.01")])
device(1, "e2_light", 10, [("in_illuminance", "be:u12/16>>4", "0.5")])
os.makedirs(os.path.join(out, "dev"), exist_ok=True)

# Accelerometer: a slow wobble around gravity on z; light: a ramp.
t = np.arange(acc_n)
acc_raw = np.stack([np.round(300 * np.sin(t / 7.0)), np.round(200 * np.cos(t / 5.0)),
                    np.round(981 + 50 * np.sin(t / 3.0))], axis=1).astype(np.int16)
light_raw = (np.arange(windows) * 97 + 100).astype(np.uint16)
with open(os.path.join(out, "dev", "iio:device0"), "wb") as f:
    f.write(acc_raw.astype("<i2").tobytes())
with open(os.path.join(out, "dev", "iio:device1"), "wb") as f:
    for v in light_raw:
        f.write(struct.pack(">H", (int(v) << 4) | 0x5))  # 4 low noise bits below the shift

acc = acc_raw.astype(np.float32) * np.float32(0.01)
light = light_raw.astype(np.float32) * np.float32(0.5)


class E2(torch.nn.Module):
    def __init__(self):
        super().__init__()
        self.gru = torch.nn.GRU(3, 8, batch_first=True)
        self.head = torch.nn.Linear(9, 2)

    def forward(self, accel, light):  # accel [10, 3] (3:10), light [1, 1] (1:1)
        seq, _ = self.gru(accel.unsqueeze(0))
        return self.head(torch.cat([seq[:, -1, :], light], dim=1))  # [1, 2] (2:1)


torch.manual_seed(7)
model = E2().eval()
with torch.no_grad():
    traced = torch.jit.trace(model, (torch.zeros(10, 3), torch.zeros(1, 1)))
    traced.save(os.path.join(out, "e2_gru.pt"))
    ref = [traced(torch.from_numpy(acc[w * 10:(w + 1) * 10]), torch.tensor([[light[w]]]))
           for w in range(windows)]
np.concatenate([r.numpy().reshape(-1) for r in ref]).astype(np.float32).tofile(
    os.path.join(out, "reference.f32"))
print("made %d windows in %s" % (windows, out))
