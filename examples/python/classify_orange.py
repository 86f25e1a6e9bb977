#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-only
"""Classify a picture with nnstreamer.Single: MobileNet v2 (ONNX) on the onnxruntime back end.

usage: examples/python/classify_orange.py [picture.raw|picture.png]
  default picture: ../shared/models/upstream/data/orange.raw (224x224 RGB bytes)
  env: NNS_BUILD_DIR (build), NNS_SHARED_DIR (../shared beside the worktree),
       NNS_SKIP_MISSING=1: exit 77 (skipped) instead of 1 when the model, picture or back end
       is missing; never in CI (CI=true), where they must be there.
prints the label ("orange" for the default picture). Run it after `. build/env.sh` (PYTHONPATH).
"""
import os
import pathlib
import sys

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
BUILD = pathlib.Path(os.environ.get("NNS_BUILD_DIR", ROOT / "build"))
SHARED = pathlib.Path(os.environ.get("NNS_SHARED_DIR", ROOT.parent / "shared")) / "models" / "upstream"
MODEL = SHARED / "models" / "mobilenet_v2_quant.onnx"
LABELS = BUILD / "data" / "imagenet_labels_1000.txt"  # the build makes it from labels.txt


def missing(what: str) -> None:
    skip = os.environ.get("NNS_SKIP_MISSING") and os.environ.get("CI") != "true"
    print(f"classify_orange: {what}", file=sys.stderr)
    sys.exit(77 if skip else 1)


def load_picture(path: pathlib.Path) -> np.ndarray:
    """224x224 RGB uint8 (H, W, C)."""
    if path.suffix == ".raw":
        return np.fromfile(path, np.uint8).reshape(224, 224, 3)
    try:
        from PIL import Image  # Debian python3-pil, only for pictures other than .raw
    except ImportError:
        sys.exit("classify_orange: reading a .png needs python3-pil (or give a .raw picture)")
    return np.asarray(Image.open(path).convert("RGB").resize((224, 224)), np.uint8)


def main() -> int:
    picture = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else SHARED / "data" / "orange.raw"
    for f in (MODEL, picture):
        if not f.is_file():
            missing(f"{f} not found")
    if not (BUILD / "subplugins" / "filters" / "libnnstreamer_filter_onnxruntime.so").is_file():
        missing("the onnxruntime back end is not built (scripts/deps/onnxruntime.npm)")
    if not LABELS.is_file():
        sys.exit(f"classify_orange: {LABELS} not generated (re-run cmake with ../shared present)")
    import nnstreamer

    # torchvision's ImageNet normalisation, then HWC -> NCHW (the model is a PyTorch export).
    rgb = load_picture(picture).astype(np.float32)
    mean = np.array([0.485, 0.456, 0.406], np.float32) * 255
    std = np.array([0.229, 0.224, 0.225], np.float32) * 255
    x = np.ascontiguousarray(((rgb - mean) / std).transpose(2, 0, 1)[np.newaxis])
    with nnstreamer.Single(str(MODEL), "onnxruntime") as model:
        (scores,) = model.invoke(x)  # x goes to ONNX Runtime without a copy
    labels = LABELS.read_text().splitlines()
    print(labels[int(np.argmax(scores))])
    return 0


if __name__ == "__main__":
    sys.exit(main())
