'use strict';
// Five random bodies of the default model: their statures, and the first one written as a glTF file.
// usage: node examples/bodies.js [OUT_DIR]
const path = require('node:path');
const sscape = require('..');

const out = process.argv[2] || '.';
const model = sscape.Model.loadDefault();
console.log(`sscape ${sscape.version().text}: ${model.vertexCount} vertices, ${model.jointCount} joints, ${model.shapeCount} shape components`);
const shapes = model.sampleShapes(5, { seed: 1 });
const body = model.createBody();
for (let i = 0; i < 5; ++i) {
  body.shape = shapes.subarray(i * model.shapeCount, (i + 1) * model.shapeCount);
  const m = body.measure();
  console.log(`body ${i}: stature ${m.stature.toFixed(3)} m, waist ${m.waist_girth.toFixed(3)} m, mass ${m.mass.toFixed(1)} kg`);
  if (i === 0) {
    body.write(path.join(out, 'body_0.glb'));
    console.log(`wrote ${path.join(out, 'body_0.glb')}`);
  }
}
body.close();
model.close();
