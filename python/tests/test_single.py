# SPDX-License-Identifier: LGPL-2.1-only
"""nnstreamer.Single: invoke with numpy arrays (no input copy, outputs over the ML API's
buffers), info, set_input_info, dynamic shapes, properties, errors, context manager."""
import ctypes
import gc
import pathlib

import numpy as np
import pytest

import nnstreamer
from conftest import backend_built, require


def probe_lib(probe: str) -> ctypes.CDLL:
    lib = ctypes.CDLL(probe)  # the same handle the custom filter back end loaded
    lib.probe_last_input.restype = ctypes.c_void_p
    lib.probe_calls.restype = ctypes.c_uint
    return lib


def test_invoke_returns_the_models_output(probe):
    with nnstreamer.Single(probe, "custom") as model:
        assert model.input_info == [nnstreamer.TensorInfo(np.dtype("uint8"), (4,), None)]
        assert model.output_info == model.input_info
        out = model.invoke(np.array([1, 2, 3, 250], np.uint8))
        assert isinstance(out, list) and len(out) == 1
        assert out[0].dtype == np.uint8 and out[0].shape == (4,)
        assert out[0].tolist() == [1, 2, 3, 250]


def test_large_float_input_is_not_copied(probe):
    """224x224x3 float32: the model reads the numpy array's own memory."""
    lib = probe_lib(probe)
    with nnstreamer.Single(probe, "custom", custom="float32,3:224:224:1") as model:
        assert model.input_info[0].shape == (1, 224, 224, 3)
        x = np.random.default_rng(1).random((1, 224, 224, 3), dtype=np.float32)
        calls = lib.probe_calls()
        (y,) = model.invoke(x)
        assert lib.probe_calls() == calls + 1
        assert lib.probe_last_input() == x.ctypes.data
        np.testing.assert_array_equal(y, x)
        # Another shape with the same size is the same tensor: still no copy.
        x2 = x.reshape(224, 224, 3)
        model.invoke(x2)
        assert lib.probe_last_input() == x2.ctypes.data
        # A non-contiguous view must be made contiguous first: a copy, elsewhere.
        big = np.zeros((1, 224, 224, 6), np.float32)
        view = big[..., ::2]
        (y,) = model.invoke(view)
        assert lib.probe_last_input() != big.ctypes.data
        np.testing.assert_array_equal(y, view)


def test_outputs_are_views_that_outlive_the_model(probe):
    model = nnstreamer.Single(probe, "custom")
    (out,) = model.invoke(np.array([9, 8, 7, 6], np.uint8))
    assert not out.flags.owndata
    assert type(out.base).__name__ == "PyCapsule"
    model.close()
    del model
    gc.collect()
    assert out.tolist() == [9, 8, 7, 6]  # the output buffer lives with the array
    out[0] = 1  # writeable
    assert out[0] == 1


def test_each_invoke_gives_new_output(probe):
    with nnstreamer.Single(probe, "custom") as model:
        (a,) = model.invoke(np.array([1, 1, 1, 1], np.uint8))
        (b,) = model.invoke(np.array([2, 2, 2, 2], np.uint8))
        assert a.tolist() == [1, 1, 1, 1] and b.tolist() == [2, 2, 2, 2]


def test_lists_are_converted(probe):
    with nnstreamer.Single(probe, "custom") as model:
        assert model.invoke([5, 6, 7, 8])[0].tolist() == [5, 6, 7, 8]


def test_wrong_dtype_is_a_type_error(probe):
    with nnstreamer.Single(probe, "custom") as model:
        with pytest.raises(TypeError, match="input 0 is float32, the model takes uint8"):
            model.invoke(np.zeros(4, np.float32))


def test_wrong_count_is_an_error_with_the_code(probe):
    with nnstreamer.Single(probe, "custom") as model:
        with pytest.raises(nnstreamer.Error, match="2 array\\(s\\) given, the model takes 1") as e:
            model.invoke(np.zeros(4, np.uint8), np.zeros(4, np.uint8))
        assert e.value.code == nnstreamer.ERROR_INVALID_PARAMETER


def test_set_input_info_changes_both_infos(probe):
    with nnstreamer.Single(probe, "custom") as model:
        model.set_input_info([(np.int16, (2, 3))])
        want = [nnstreamer.TensorInfo(np.dtype("int16"), (2, 3), None)]
        assert model.input_info == want and model.output_info == want
        x = np.arange(6, dtype=np.int16).reshape(2, 3)
        np.testing.assert_array_equal(model.invoke(x)[0], x)
        model.set_input_info([nnstreamer.TensorInfo(np.dtype("float64"), (5,), "in")])
        assert model.input_info[0].name == "in"
        assert model.output_info[0].shape == (5,)


def test_another_size_runs_invoke_dynamic(probe):
    with nnstreamer.Single(probe, "custom") as model:
        x = np.arange(10, dtype=np.uint8).reshape(2, 5)
        (y,) = model.invoke(x)
        assert y.shape == (2, 5)
        np.testing.assert_array_equal(y, x)
        assert model.input_info[0].shape == (2, 5)  # the handle follows, as NNStreamer's


def test_input_info_option_and_properties(probe):
    with nnstreamer.Single(probe, "custom", input_info=[(np.uint8, (1, 8))],
                           is_updatable=True) as model:
        assert model.input_info[0].shape == (1, 8)
        assert model.get_property("framework") == "custom"
        assert model.get_property("is-updatable") == "true"
        assert model.get_property("input") == "8:1"
        with pytest.raises(nnstreamer.Error, match="unknown|not supported|known") as e:
            model.set_property("no-such-property", "1")
        assert e.value.code == nnstreamer.ERROR_NOT_SUPPORTED


def test_closed_model_raises(probe):
    model = nnstreamer.Single(probe, "custom")
    with model:
        pass
    with pytest.raises(nnstreamer.Error, match="closed"):
        model.invoke(np.zeros(4, np.uint8))
    model.close()  # twice is fine


def test_open_errors_carry_ml_error_text(tmp_path: pathlib.Path):
    missing = tmp_path / "missing.onnx"
    with pytest.raises(nnstreamer.Error, match="missing.onnx' is not a file") as e:
        nnstreamer.Single(str(missing), "onnxruntime")
    assert e.value.code == nnstreamer.ERROR_INVALID_PARAMETER
    pb = tmp_path / "model.pb"
    pb.write_bytes(b"not a model")
    with pytest.raises(nnstreamer.Error, match="framework 'tensorflow' is not available") as e:
        nnstreamer.Single(str(pb), "tensorflow")
    assert e.value.code == nnstreamer.ERROR_NOT_SUPPORTED
    assert isinstance(e.value, RuntimeError)


def test_timeout_option(probe):
    with nnstreamer.Single(probe, "custom", timeout=5000) as model:
        assert model.invoke(np.array([1, 2, 3, 4], np.uint8))[0].tolist() == [1, 2, 3, 4]


def test_mobilenet_onnxruntime_classifies_the_orange(shared_models):
    model_path = shared_models / "models" / "mobilenet_v2_quant.onnx"
    raw = shared_models / "data" / "orange.raw"
    require(model_path.is_file() and raw.is_file(), f"{model_path} or {raw} missing")
    require(backend_built("onnxruntime"), "the onnxruntime back end is not built")
    with nnstreamer.Single(str(model_path), "onnxruntime") as model:
        (spec,) = model.input_info
        rgb = np.fromfile(raw, np.uint8).reshape(224, 224, 3).astype(np.float32)
        mean = np.array([0.485, 0.456, 0.406], np.float32) * 255
        std = np.array([0.229, 0.224, 0.225], np.float32) * 255
        x = np.ascontiguousarray(((rgb - mean) / std).transpose(2, 0, 1)[None])
        assert spec.dtype == np.float32 and spec.shape == x.shape
        (scores,) = model.invoke(x)
        assert int(np.argmax(scores)) == 950  # "orange" among the 1000 ImageNet classes


def test_python3_back_end_runs_in_this_interpreter():
    """framework=python3 inside a Python process: the back end shares this interpreter."""
    require(backend_built("python3"), "the python3 back end is not built")
    script = pathlib.Path(__file__).parents[2] / "tests" / "data" / "python" / "identity.py"
    spec = [(np.float32, (4,))]
    with nnstreamer.Single(str(script), "python3", input_info=spec, output_info=spec) as model:
        x = np.array([0.5, -1.0, 2.0, 3.5], np.float32)
        (y,) = model.invoke(x)
        np.testing.assert_array_equal(y.ravel(), x)


def test_close_while_other_threads_invoke(probe):
    """close() waits for invokes running without the GIL; later ones raise "closed"."""
    import threading

    model = nnstreamer.Single(probe, "custom", custom="float32,3:64:64:1")
    x = np.ones((1, 64, 64, 3), np.float32)
    errors, done = [], []

    def worker():
        try:
            for _ in range(2000):
                np.testing.assert_array_equal(model.invoke(x)[0], x)
        except nnstreamer.Error as e:
            errors.append(str(e))
        done.append(1)

    threads = [threading.Thread(target=worker) for _ in range(3)]
    for t in threads:
        t.start()
    model.close()
    for t in threads:
        t.join(30)
    assert len(done) == 3
    assert all("closed" in e for e in errors)
