'use strict';
// What calls cost through the binding: a trivial call, and a body's vertices after a shape change
// (what an engine does per frame), as medians of 5 runs. Compare with tests/bindings/bench.c.
// usage: node examples/bench.js
const sscape = require('..');

function median(f, repeats) {
  const times = [];
  for (let r = 0; r < 5; ++r) {
    const start = process.hrtime.bigint();
    for (let i = 0; i < repeats; ++i) f(i);
    times.push(Number(process.hrtime.bigint() - start) / repeats);
  }
  return times.sort((a, b) => a - b)[2];
}

const model = sscape.Model.loadDefault();
const body = model.createBody();
const native = sscape.native;
const shapes = model.sampleShapes(16, { seed: 1 });
const K = model.shapeCount;
const out = new Float32Array(model.vertexCount * 3);
const call = median(() => native.ssc_model_vertex_count(model.handle), 100000);
const vertices = median((i) => {
  native.ssc_body_set_shape(body.handle, shapes.subarray((i % 16) * K, (i % 16 + 1) * K), K);
  native.ssc_body_get_vertices(body.handle, out, model.vertexCount, 0);
}, 300);
const idiomatic = median((i) => { body.shape = shapes.subarray((i % 16) * K, (i % 16 + 1) * K); return body.vertices; }, 300);
console.log(`javascript: call ${call.toFixed(0)} ns, shape+vertices ${(vertices / 1000).toFixed(1)} us (idiomatic, new arrays: ${(idiomatic / 1000).toFixed(1)} us)`);
body.close();
model.close();
