// Compiled (not run) by test.sh with tsc --strict: the TypeScript declarations (index.d.ts) fit the package's use.
import * as sscape from 'sscape';
const model: sscape.Model = sscape.Model.loadDefault();
const body = model.createBody();
body.shape = new Float32Array([0.8, -0.5]);
body.setPose(null, [0, 0, 0]);
const v: Float32Array = body.vertices;
const m: Record<string, number> = body.measure();
const fitter = model.createFitter({ max_iterations: 20 });
fitter.addLandmarks(model.landmarkNames, body.landmarks);
const report: sscape.FitReport = fitter.solve({ onProgress: (i: number, c: number) => i > 100 });
const pose = fitter.pose();
const s: number = pose.scale;
const segments: sscape.Segment[] = model.segments;
body.setSegmentShape(model.segmentIndex('head'), [1.0]);
const head: Float32Array = body.segmentShape(model.segmentIndex('head'), segments[0].shapeCount);
const levels: sscape.Level[] = model.levels;
const far: Float32Array = body.levelVertices(model.level('proxy741').index);
body.write('/tmp/sscape-types-check.glb', 'glb', { level: levels.length - 1 });
const batch = model.synthesize({ shapes: model.sampleShapes(2, { seed: 1 }) }).vertices;
try { model.jointIndex('x'); } catch (e) { if (e instanceof sscape.SscapeError) console.log(e.code, e.status); }
console.log(v.length, head.length, far.length, m.stature, report.iterations, s, batch.length, sscape.version().major, sscape.measurements()[0].unit);
body.close(); fitter.close(); model.close();
