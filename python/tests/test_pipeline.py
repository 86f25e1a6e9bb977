# SPDX-License-Identifier: LGPL-2.1-only
"""nnstreamer.Pipeline: sink callbacks with numpy arrays, appsrc push, state, element
properties, switch and valve, errors carrying ml_error() text."""
import sys
import threading
import time

import numpy as np
import pytest

import nnstreamer


def tensor_caps(dims: str, types: str) -> str:
    return (f"other/tensors,format=static,num_tensors=1,dimensions={dims},types={types},"
            "framerate=0/1")


class Frames:
    """Collects sink callbacks; wait(n) blocks until n frames arrived (or fails)."""

    def __init__(self):
        self.items = []
        self.threads = set()
        self.cond = threading.Condition()

    def __call__(self, arrays, info):
        with self.cond:
            self.items.append((arrays, info))
            self.threads.add(threading.get_ident())
            self.cond.notify_all()

    def wait(self, n: int, timeout: float = 10.0) -> None:
        with self.cond:
            assert self.cond.wait_for(lambda: len(self.items) >= n, timeout), \
                f"{len(self.items)} frame(s) after {timeout} s, expected {n}"


def test_sink_callback_counts_frames_on_a_streaming_thread():
    frames = Frames()
    states = []
    desc = ("videotestsrc num-buffers=7 ! video/x-raw,format=RGB,width=4,height=2 ! "
            "tensor_converter ! tensor_sink name=out")
    with nnstreamer.Pipeline(desc, on_state=states.append) as pipe:
        assert pipe.state == nnstreamer.State.PAUSED
        pipe.on_sink("out", frames)
        pipe.start()
        frames.wait(7)
        time.sleep(0.1)
        assert len(frames.items) == 7
        arrays, info = frames.items[0]
        assert info == [nnstreamer.TensorInfo(np.dtype("uint8"), (1, 2, 4, 3), None)]
        assert arrays[0].shape == (1, 2, 4, 3) and arrays[0].dtype == np.uint8
        assert arrays[0].flags.owndata is False  # a view over the library's copy
        assert threading.get_ident() not in frames.threads
    assert nnstreamer.State.PAUSED in states and nnstreamer.State.PLAYING in states
    assert all(isinstance(s, nnstreamer.State) for s in states)


def test_push_into_appsrc_reaches_the_sink():
    frames = Frames()
    desc = (f"appsrc name=src caps={tensor_caps('4:1:1:1', 'float32')} ! "
            "tensor_sink name=out async=false")
    with nnstreamer.Pipeline(desc) as pipe:
        pipe.on_sink("out", frames)
        pipe.start()
        x = np.array([[1.5, -2.0, 3.25, 0.0]], np.float32)
        pipe.push("src", x)
        pipe.push("src", [x * 2])
        frames.wait(2)
        assert frames.items[0][0][0].shape == (1, 1, 1, 4)  # the caps' 4:1:1:1
        np.testing.assert_array_equal(frames.items[0][0][0].reshape(1, 4), x)
        np.testing.assert_array_equal(frames.items[1][0][0].reshape(1, 4), x * 2)
        x[0, 0] = 99  # the pipeline has its own copy
        np.testing.assert_array_equal(frames.items[0][0][0].ravel()[0], 1.5)
        with pytest.raises(nnstreamer.Error, match="expects 16 bytes") as e:
            pipe.push("src", np.zeros(3, np.float32))
        assert e.value.code == nnstreamer.ERROR_INVALID_PARAMETER
        with pytest.raises(nnstreamer.Error, match="no element named 'nope'"):
            pipe.push("nope", x)
        pipe.end_of_stream("src")


def test_unregistered_callback_is_not_called_again():
    frames = Frames()
    desc = f"appsrc name=src caps={tensor_caps('2:1:1:1', 'uint8')} ! tensor_sink name=out async=false"
    with nnstreamer.Pipeline(desc) as pipe:
        pipe.on_sink("out", frames)
        pipe.start()
        pipe.push("src", np.array([1, 2], np.uint8))
        frames.wait(1)
        pipe.on_sink("out", None)
        pipe.push("src", np.array([3, 4], np.uint8))
        time.sleep(0.2)
        assert len(frames.items) == 1


def test_exception_in_callback_is_reported_not_fatal(monkeypatch):
    calls = []
    reported = []
    monkeypatch.setattr(sys, "unraisablehook", lambda u: reported.append(u))

    def bad(arrays, info):
        calls.append(1)
        raise ValueError("boom from the callback")

    desc = f"appsrc name=src caps={tensor_caps('2:1:1:1', 'uint8')} ! tensor_sink name=out async=false"
    with nnstreamer.Pipeline(desc) as pipe:
        pipe.on_sink("out", bad)
        pipe.start()
        pipe.push("src", np.array([1, 2], np.uint8))
        pipe.push("src", np.array([1, 2], np.uint8))
        deadline = time.time() + 5
        while len(calls) < 2 and time.time() < deadline:
            time.sleep(0.01)
    assert len(calls) == 2
    assert [str(u.exc_value) for u in reported] == ["boom from the callback"] * 2
    assert "sink callback" in str(reported[0].object)


def test_element_properties_by_type():
    desc = ("videotestsrc name=vt num-buffers=1 is-live=false ! "
            "tensor_converter name=conv ! tensor_sink name=out")
    with nnstreamer.Pipeline(desc) as pipe:
        vt = pipe.element("vt").props
        assert vt["num-buffers"] == 1
        vt["num-buffers"] = 5
        assert vt["num-buffers"] == 5
        assert vt["is-live"] is False
        vt["is-live"] = True
        assert vt["is-live"] is True
        out = pipe.element("out")
        assert out.name == "out"
        out.props["emit-signal"] = False
        assert out.props["emit-signal"] is False
        with pytest.raises(nnstreamer.Error, match="no-such-prop"):
            vt["no-such-prop"]
        with pytest.raises(nnstreamer.Error, match="no element named 'nope'"):
            pipe.element("nope")


def test_valve_and_output_selector():
    frames0, frames1, seen = Frames(), Frames(), Frames()
    # tee sends each frame through the valve branch first, then to `all`: once `all` has
    # frame k, the valve has passed or dropped it (appsrc pushes on its own thread).
    desc = (f"appsrc name=src caps={tensor_caps('2:1:1:1', 'uint8')} ! tee name=t "
            "t. ! valve name=v drop=false ! output-selector name=outs "
            "outs.src_0 ! tensor_sink name=s0 async=false "
            "outs.src_1 ! tensor_sink name=s1 async=false "
            "t. ! tensor_sink name=all async=false")
    with nnstreamer.Pipeline(desc) as pipe:
        sw = pipe.switch("outs")
        assert sw.type == "output-selector"
        assert sorted(sw.pads) == ["src_0", "src_1"]
        valve = pipe.valve("v")
        pipe.on_sink("s0", frames0)
        pipe.on_sink("s1", frames1)
        pipe.on_sink("all", seen)
        pipe.start()
        sw.select("src_0")
        pipe.push("src", np.array([1, 0], np.uint8))
        seen.wait(1)
        sw.select("src_1")
        pipe.push("src", np.array([2, 0], np.uint8))
        seen.wait(2)
        valve.open = False
        pipe.push("src", np.array([3, 0], np.uint8))
        seen.wait(3)
        valve.set_open(True)
        pipe.push("src", np.array([4, 0], np.uint8))
        seen.wait(4)
        assert [a[0].ravel().tolist() for a, _ in frames0.items] == [[1, 0]]
        assert [a[0].ravel().tolist() for a, _ in frames1.items] == [[2, 0], [4, 0]]
        with pytest.raises(nnstreamer.Error, match="no selectable pad 'src_7'"):
            sw.select("src_7")
        with pytest.raises(nnstreamer.Error, match="'s0' is a tensor_sink, not a valve"):
            pipe.valve("s0")
    with pytest.raises(nnstreamer.Error, match="closed"):
        valve.set_open(False)
    with pytest.raises(nnstreamer.Error, match="closed"):
        pipe.start()


def test_construct_errors_name_the_cause():
    with pytest.raises(nnstreamer.Error, match="tensor_fitler") as e:
        nnstreamer.Pipeline("videotestsrc ! tensor_fitler ! fakesink")
    assert e.value.code == nnstreamer.ERROR_STREAMS_PIPE
    assert "unknown element" in str(e.value)
