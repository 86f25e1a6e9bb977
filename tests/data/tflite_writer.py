# SPDX-License-Identifier: LGPL-2.1-only
"""A minimal TensorFlow Lite flatbuffer writer (no TensorFlow needed) and the .tflite twins of
the conformance models in generate_models.py.

Only python3-flatbuffers' Builder is used; tables, field ids and enum values follow the public
TensorFlow Lite schema (tensorflow/lite/schema/schema.fbs, file identifier "TFL3", version 3).
Field ids used here:
  Model          0 version, 1 operator_codes, 2 subgraphs, 3 description, 4 buffers
  OperatorCode   0 deprecated_builtin_code (byte; "builtin_code" in older schemas, which is what
                 Arm NN 20.08 reads), 2 version, 3 builtin_code (int, newer readers)
  SubGraph       0 tensors, 1 inputs, 2 outputs, 3 operators, 4 name
  Tensor         0 shape, 1 type, 2 buffer, 3 name, 4 quantization
  Quantization   2 scale, 3 zero_point
  Operator       0 opcode_index, 1 inputs, 2 outputs, 3 builtin_options_type, 4 builtin_options
  Buffer         0 data (aligned to 16); buffer 0 is the empty sentinel of tensors without data
"""

import flatbuffers
import numpy as np

# BuiltinOperator values.
ADD, CONV_2D, DEQUANTIZE, FULLY_CONNECTED = 0, 3, 6, 9
MAX_POOL_2D, MUL, RESHAPE, SOFTMAX, TRANSPOSE, MEAN = 17, 18, 22, 25, 39, 40

# BuiltinOptions union member index (NONE = 0) and the options table each operator uses.
OPTIONS = {
    ADD: 11,  # AddOptions {fused_activation_function}
    CONV_2D: 1,  # Conv2DOptions {padding, stride_w, stride_h, fused_activation_function}
    DEQUANTIZE: 38,  # DequantizeOptions {}
    FULLY_CONNECTED: 8,  # FullyConnectedOptions {fused_activation_function}
    MAX_POOL_2D: 5,  # Pool2DOptions {padding, stride_w, stride_h, filter_width, filter_height}
    MUL: 21,  # MulOptions {fused_activation_function}
    RESHAPE: 17,  # ReshapeOptions {new_shape}
    SOFTMAX: 9,  # SoftmaxOptions {beta}
    TRANSPOSE: 26,  # TransposeOptions {}
    MEAN: 27,  # ReducerOptions {keep_dims}
}

TENSOR_TYPES = {np.dtype(np.float32): 0, np.dtype(np.int32): 2, np.dtype(np.uint8): 3}
PAD_SAME, PAD_VALID = 0, 1
ACT_NONE, ACT_RELU = 0, 1


class Graph:
    """One subgraph being built: tensors, constant buffers, operators in execution order."""

    def __init__(self):
        self.tensors = []  # (name, shape, dtype, buffer index, (scale, zero_point) or None)
        self.buffers = [b""]  # buffer 0: the sentinel
        self.opcodes = []  # builtin codes, in first-use order
        self.ops = []  # (opcode index, inputs, outputs, options type, [(slot, kind, value)])
        self.inputs, self.outputs = [], []

    def tensor(self, name, shape, dtype, quant=None):
        self.tensors.append((name, list(shape), np.dtype(dtype), 0, quant))
        return len(self.tensors) - 1

    def const(self, name, array):
        array = np.ascontiguousarray(array)
        self.buffers.append(array.astype(array.dtype.newbyteorder("<")).tobytes())
        self.tensors.append((name, list(array.shape), array.dtype, len(self.buffers) - 1, None))
        return len(self.tensors) - 1

    def op(self, code, inputs, outputs, fields=()):
        """fields: (slot, kind, value) of the operator's options table; kind i8, i32, f32, vi32."""
        if code not in self.opcodes:
            self.opcodes.append(code)
        self.ops.append((self.opcodes.index(code), inputs, outputs, OPTIONS[code], list(fields)))

    def serialize(self, description):
        b = flatbuffers.Builder(4096)

        def ints(values, dtype=np.int32):
            return b.CreateNumpyVector(np.asarray(values, dtype=dtype))

        def offsets(offs):
            b.StartVector(4, len(offs), 4)
            for o in reversed(offs):
                b.PrependUOffsetTRelative(o)
            return b.EndVector()

        def table(fields):
            # Vectors first: a table's children are written before the table itself.
            vecs = {slot: ints(v) for slot, kind, v in fields if kind == "vi32"}
            b.StartObject(8)
            for slot, kind, v in fields:
                if kind == "i8":
                    b.PrependInt8Slot(slot, v, 0)
                elif kind == "i32":
                    b.PrependInt32Slot(slot, v, 0)
                elif kind == "f32":
                    b.PrependFloat32Slot(slot, v, 0.0)
                else:
                    b.PrependUOffsetTRelativeSlot(slot, vecs[slot], 0)
            return b.EndObject()

        buffers = []
        for data in self.buffers:
            vec = None
            if data:
                b.StartVector(1, len(data), 16)
                b.head = b.Head() - len(data)
                b.Bytes[b.Head():b.Head() + len(data)] = data
                vec = b.EndVector()
            b.StartObject(1)
            if vec is not None:
                b.PrependUOffsetTRelativeSlot(0, vec, 0)
            buffers.append(b.EndObject())

        tensors = []
        for name, shape, dtype, buf, quant in self.tensors:
            shape_v, name_s = ints(shape), b.CreateString(name)
            q = None
            if quant:
                scale_v = b.CreateNumpyVector(np.array([quant[0]], dtype=np.float32))
                zero_v = ints([quant[1]], np.int64)
                b.StartObject(7)
                b.PrependUOffsetTRelativeSlot(2, scale_v, 0)
                b.PrependUOffsetTRelativeSlot(3, zero_v, 0)
                q = b.EndObject()
            b.StartObject(5)
            b.PrependUOffsetTRelativeSlot(0, shape_v, 0)
            b.PrependInt8Slot(1, TENSOR_TYPES[dtype], 0)
            b.PrependUint32Slot(2, buf, 0)
            b.PrependUOffsetTRelativeSlot(3, name_s, 0)
            if q is not None:
                b.PrependUOffsetTRelativeSlot(4, q, 0)
            tensors.append(b.EndObject())

        ops = []
        for opcode, ins, outs, opt_type, fields in self.ops:
            ins_v, outs_v, opt = ints(ins), ints(outs), table(fields)
            b.StartObject(5)
            b.PrependUint32Slot(0, opcode, 0)
            b.PrependUOffsetTRelativeSlot(1, ins_v, 0)
            b.PrependUOffsetTRelativeSlot(2, outs_v, 0)
            b.PrependUint8Slot(3, opt_type, 0)
            b.PrependUOffsetTRelativeSlot(4, opt, 0)
            ops.append(b.EndObject())

        codes = []
        for code in self.opcodes:
            b.StartObject(4)
            b.PrependInt8Slot(0, code, 0)  # deprecated_builtin_code
            b.PrependInt32Slot(2, 1, 0)  # version
            b.PrependInt32Slot(3, code, 0)  # builtin_code
            codes.append(b.EndObject())

        tensors_v, ops_v = offsets(tensors), offsets(ops)
        in_v, out_v, sg_name = ints(self.inputs), ints(self.outputs), b.CreateString("main")
        b.StartObject(5)
        b.PrependUOffsetTRelativeSlot(0, tensors_v, 0)
        b.PrependUOffsetTRelativeSlot(1, in_v, 0)
        b.PrependUOffsetTRelativeSlot(2, out_v, 0)
        b.PrependUOffsetTRelativeSlot(3, ops_v, 0)
        b.PrependUOffsetTRelativeSlot(4, sg_name, 0)
        subgraph = b.EndObject()

        codes_v, sgs_v, bufs_v = offsets(codes), offsets([subgraph]), offsets(buffers)
        desc = b.CreateString(description)
        b.StartObject(5)
        b.PrependUint32Slot(0, 3, 0)
        b.PrependUOffsetTRelativeSlot(1, codes_v, 0)
        b.PrependUOffsetTRelativeSlot(2, sgs_v, 0)
        b.PrependUOffsetTRelativeSlot(3, desc, 0)
        b.PrependUOffsetTRelativeSlot(4, bufs_v, 0)
        b.Finish(b.EndObject(), file_identifier=b"TFL3")
        return bytes(b.Output())


def add_mul(inputs, in_names, out_names):
    g = Graph()
    a = g.tensor(in_names[0], inputs[0].shape, np.float32)
    c = g.tensor(in_names[1], inputs[1].shape, np.float32)
    s = g.tensor(out_names[0], inputs[0].shape, np.float32)
    p = g.tensor(out_names[1], inputs[0].shape, np.float32)
    g.op(ADD, [a, c], [s], [(0, "i8", ACT_NONE)])
    g.op(MUL, [a, c], [p], [(0, "i8", ACT_NONE)])
    g.inputs, g.outputs = [a, c], [s, p]
    return g


def conv_net(module, inputs, in_names, out_names):
    """NCHW input as in torch; transposed once to NHWC, the layout of TFLite's CONV_2D. The
    fully-connected weights are permuted to NHWC flattening order, so no transpose back."""
    w = {k: v.detach().numpy().astype(np.float32) for k, v in module.state_dict().items()}
    n, c, h, wd = inputs[0].shape
    g = Graph()
    x = g.tensor(in_names[0], (n, c, h, wd), np.float32)
    y = g.tensor("image_nhwc", (n, h, wd, c), np.float32)
    g.op(TRANSPOSE, [x, g.const("to_nhwc", np.array([0, 2, 3, 1], np.int32))], [y])
    for i, name in enumerate(["conv1", "conv2"]):
        kw = w[name + ".weight"]  # O, I, H, W -> O, H, W, I
        filt = g.const(name + ".weight", kw.transpose(0, 2, 3, 1))
        bias = g.const(name + ".bias", w[name + ".bias"])
        conv = g.tensor(name, (n, h, wd, kw.shape[0]), np.float32)
        g.op(CONV_2D, [y, filt, bias], [conv],
             [(0, "i8", PAD_SAME), (1, "i32", 1), (2, "i32", 1), (3, "i8", ACT_RELU)])
        h, wd = h // 2, wd // 2
        y = g.tensor(name + "_pool", (n, h, wd, kw.shape[0]), np.float32)
        g.op(MAX_POOL_2D, [conv], [y], [(0, "i8", PAD_VALID), (1, "i32", 2), (2, "i32", 2),
                                        (3, "i32", 2), (4, "i32", 2), (5, "i8", ACT_NONE)])
    fc = w["fc.weight"]  # [out, C*H*W] in torch's NCHW flattening
    ch = fc.shape[1] // (h * wd)
    fc_nhwc = fc.reshape(-1, ch, h, wd).transpose(0, 2, 3, 1).reshape(fc.shape[0], -1)
    flat = g.tensor("flat", (n, fc.shape[1]), np.float32)
    g.op(RESHAPE, [y], [flat], [(0, "vi32", [n, fc.shape[1]])])
    logits = g.tensor(out_names[0], (n, fc.shape[0]), np.float32)
    g.op(FULLY_CONNECTED, [flat, g.const("fc.weight", fc_nhwc), g.const("fc.bias", w["fc.bias"])],
         [logits], [(0, "i8", ACT_NONE)])
    probs = g.tensor(out_names[1], (n, fc.shape[0]), np.float32)
    g.op(SOFTMAX, [logits], [probs], [(0, "f32", 1.0)])
    g.inputs, g.outputs = [x], [logits, probs]
    return g


def uint8_scale(inputs, in_names, out_names):
    """uint8 input quantized with scale 1/255, zero point 0: DEQUANTIZE gives x / 255."""
    shape = inputs[0].shape
    g = Graph()
    x = g.tensor(in_names[0], shape, np.uint8, quant=(np.float32(1.0 / 255.0), 0))
    f = g.tensor("pixels_float", shape, np.float32)
    g.op(DEQUANTIZE, [x], [f])
    m = g.tensor(out_names[0], shape[:-1], np.float32)
    g.op(MEAN, [f, g.const("channel_axis", np.array([len(shape) - 1], np.int32))], [m],
         [(0, "i8", 0)])  # keep_dims false
    g.inputs, g.outputs = [x], [m]
    return g


def write(path, name, module, inputs, in_names, out_names, description):
    """Writes NAME.tflite; returns False when the model has no TFLite twin here."""
    if name == "add_mul":
        g = add_mul(inputs, in_names, out_names)
    elif name == "conv_net":
        g = conv_net(module, inputs, in_names, out_names)
    elif name == "uint8_scale":
        g = uint8_scale(inputs, in_names, out_names)
    else:
        return False
    with open(path, "wb") as f:
        f.write(g.serialize(description))
    return True
