// SPDX-License-Identifier: LGPL-2.1-only
// Runs a .tflite model once on TensorFlow Lite itself (the WebAssembly build of TFLite 2.x that
// npm's @tensorflow/tfjs-tflite ships, its default CPU path) and writes each output tensor's raw
// bytes. Used once to make the golden outputs of tests/data/tflite (scripts/tflite-goldens.sh);
// not run by the tests.
//   node tflite_reference.js <tfjs-tflite dir> <model.tflite> <out prefix> <input.raw>...
// Inputs are the raw bytes of each input tensor in order; outputs go to <prefix>.<k>.raw, and
// one line per tensor (name, type, shape) to stdout.
'use strict';
const fs = require('fs');
const path = require('path');

async function main() {
  const [dir, model, prefix, ...inputs] = process.argv.slice(2);
  if (!dir || !model || !prefix) {
    console.error('usage: node tflite_reference.js <tfjs-tflite dir> <model> <prefix> <in.raw>...');
    process.exit(2);
  }
  const wasm = path.join(dir, 'wasm');
  const factory = require(path.join(wasm, 'tflite_web_api_cc.js'));  // no SIMD, no threads
  const M = await factory({wasmBinary: fs.readFileSync(path.join(wasm, 'tflite_web_api_cc.wasm'))});
  const bytes = fs.readFileSync(model);
  const p = M._malloc(bytes.length);
  M.HEAPU8.set(bytes, p);
  const r = M.TFLiteWebModelRunner.CreateFromBufferAndOptions(
      p, bytes.length, {numThreads: 1, enableProfiling: false, maxProfilingBufferEntries: 1024});
  if (!r.ok()) throw new Error(model + ': ' + r.errorMessage());
  const runner = r.value();
  const ins = runner.GetInputs();
  if (ins.size() !== inputs.length)
    throw new Error(`${model} has ${ins.size()} inputs, ${inputs.length} files given`);
  for (let k = 0; k < ins.size(); ++k) {
    const t = ins.get(k), view = t.data();
    const raw = fs.readFileSync(inputs[k]);
    if (raw.length !== view.byteLength)
      throw new Error(`${inputs[k]}: ${raw.length} bytes, input ${t.name} needs ${view.byteLength}`);
    new Uint8Array(view.buffer, view.byteOffset, view.byteLength).set(raw);
  }
  if (!runner.Infer()) throw new Error(model + ': Infer failed');
  const outs = runner.GetOutputs();
  for (let k = 0; k < outs.size(); ++k) {
    const t = outs.get(k), view = t.data();
    fs.writeFileSync(`${prefix}.${k}.raw`,
                     Buffer.from(new Uint8Array(view.buffer, view.byteOffset, view.byteLength)));
    console.log(`output ${k}: ${t.name} ${t.dataType} [${t.shape}]`);
  }
}
main().catch(e => {
  console.error(e.message || e);
  process.exit(1);
});
