// Compiled (not run) by the web_package_types test: the browser package's declarations type-check
// as a page would use them (tsc --strict).
import { loadRuntime, SscapeError, type Model, type Body, type Slider, type Level, type FitReport } from '../../bindings/web/index';

async function configure(): Promise<Uint8Array> {
  const sscape = await loadRuntime({ wasm: 'sscape_runtime.wasm' });
  const model: Model = await sscape.loadModel('sscape-default.sscape');
  const levels: Level[] = model.levels;
  const sliders: Slider[] = model.sliders;
  const body: Body = model.createBody();
  body.setSlider(sliders[0].name, sliders[0].mean);
  body.setNamedPose('sitting', { handsClosed: [0.5, 0.5] });
  const fitted: { converged: boolean; achieved: Record<string, number> } = body.makeToMeasure({ waist_girth: 0.9 }, { sex: 0 });
  const vertices: Float32Array = body.levelVertices(levels[levels.length - 1].name);
  const stature: number = body.measure().stature + vertices[1] * 0 + (fitted.converged ? 0 : 1);
  try {
    sscape.modelFromBytes(new Uint8Array(4));
  } catch (e) {
    if (e instanceof SscapeError) console.log(e.code, e.status, stature);
  }
  const fitter = model.createFitter({ shapeCount: 10 });
  fitter.addLandmarks(model.landmarkNames, body.landmarks);
  const report: FitReport = fitter.solve();
  if (!report.converged) throw new Error(String(report.problem));
  return body.toGLB({ level: 'all', morphs: 'sliders' });
}
void configure();
