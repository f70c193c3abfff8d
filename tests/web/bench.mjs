// The browser benchmark (issue 50): synthesis in headless Chromium against the native library on the
// same machine, in one run, rounds alternated; the page's ready time; the sizes a page downloads.
//
// usage: node bench.mjs WEB_DIR NODE_MODULES SSCAPE_BENCH [ROUNDS]
//   WEB_DIR       build-wasm/web;  NODE_MODULES: with puppeteer-core (build/npm/node_modules)
//   SSCAPE_BENCH  build/tests/bench/sscape_bench (the native side: BM_PoseOnlyLevel, BM_ShapeAndPoseLevel), run on
//                 its AVX2 kernels (WebAssembly SIMD is 128 bits; AVX-512 machines would otherwise compare
//                 against wider vectors than the ratio's target assumes); SSCAPE_ISA set by the caller wins
// The browser side runs the same loops as the native benchmark through the module's raw exports (the
// C calls alone, parameters and output buffers on the WebAssembly heap): pose only (the shape set
// once) and shape + pose, of the full mesh and of the lowest level, random parameters as the native
// benchmark draws them (standard normal shapes, 0.3 rad normal axis-angle poses).
import fs from 'node:fs';
import path from 'node:path';
import zlib from 'node:zlib';
import { execFileSync } from 'node:child_process';
import { createRequire } from 'node:module';
import { serve } from './static_server.mjs';

const [webDir, nodeModules, nativeBench, roundsArg] = process.argv.slice(2);
const rounds = Number(roundsArg ?? 3);
const puppeteer = createRequire(path.join(path.resolve(nodeModules), 'x.js'))('puppeteer-core');
const chromium = ['/usr/bin/chromium', '/usr/bin/chromium-browser'].find((p) => fs.existsSync(p));

// What each row measures: [name, native benchmark, level (-1: the lowest), shape each iteration].
const rows = [['pose only, full mesh', 'BM_PoseOnlyLevel/0', 0, false], ['pose only, lowest level', 'BM_PoseOnlyLevel/3', -1, false],
  ['shape + pose, full mesh', 'BM_ShapeAndPoseLevel/0', 0, true], ['shape + pose, lowest level', 'BM_ShapeAndPoseLevel/3', -1, true]];

function nativeRound() {
  const out = execFileSync(nativeBench, ['--benchmark_filter=BM_PoseOnlyLevel/(0|3)$|BM_ShapeAndPoseLevel/(0|3)$', '--benchmark_min_time=0.3',
    '--benchmark_format=json'], { encoding: 'utf8', maxBuffer: 1 << 24, env: { ...process.env, SSCAPE_ISA: process.env.SSCAPE_ISA ?? 'avx2' } });
  const times = {};
  for (const b of JSON.parse(out).benchmarks) times[b.name] = b.real_time * (b.time_unit === 'ns' ? 1e-3 : b.time_unit === 'ms' ? 1e3 : 1);
  return rows.map(([, name]) => times[name]);
}

async function browserRound(server) {
  const browser = await puppeteer.launch({ executablePath: chromium, headless: true, args: ['--no-sandbox', '--enable-unsafe-swiftshader'] });
  try {
    const page = await browser.newPage();
    await page.setViewport({ width: 1280, height: 800 });
    await page.goto(server.url);
    await page.waitForFunction(() => window.sscapeApp?.ready, { timeout: 60000 });
    return await page.evaluate((rowsIn) => {
      const { sscape, model } = window.sscapeApp;
      const m = sscape._m;
      const J = model.jointCount, K = model.shapeCount, lowest = model.levels.length - 1;
      // Random parameters, 64 of each, as the native benchmark's pool.
      let seed = 42;
      const uniform = () => ((seed = (Math.imul(seed, 1664525) + 1013904223) >>> 0) + 0.5) / 4294967296;
      const normal = () => Math.sqrt(-2 * Math.log(uniform())) * Math.cos(2 * Math.PI * uniform());
      const shapes = m._malloc(64 * K * 4), poses = m._malloc(64 * J * 3 * 4), out = m._malloc(model.vertexCount * 12);
      for (let i = 0; i < 64 * K; ++i) m.HEAPF32[(shapes >>> 2) + i] = normal();
      for (let i = 0; i < 64 * J * 3; ++i) m.HEAPF32[(poses >>> 2) + i] = 0.3 * normal();
      const body = model.createBody(), h = body.handle;
      const results = rowsIn.map(([, , levelIn, withShape]) => {
        const level = levelIn < 0 ? lowest : levelIn, n = model.levels[level].vertexCount;
        m._ssc_body_set_shape(h, shapes, K);
        const step = (i) => {
          if (withShape) m._ssc_body_set_shape(h, shapes + (i % 64) * K * 4, K);
          m._ssc_body_set_pose_axis_angle(h, poses + (i % 64) * J * 12, J, 0);
          if (m._ssc_body_get_level_vertices(h, level, out, n, 0) !== 0) throw new Error(sscape._string(m._ssc_last_error()));
        };
        for (let i = 0; i < 200; ++i) step(i);  // warm-up: the engine's optimizing tiers
        // Repeats of at least 0.3 s each; the median repeat's time per body.
        const perBody = [];
        for (let r = 0; r < 5; ++r) {
          let count = 0;
          const t0 = performance.now();
          while (performance.now() - t0 < 300) for (let i = 0; i < 50; ++i) step(count++);
          perBody.push((performance.now() - t0) * 1000 / count);
        }
        perBody.sort((a, b) => a - b);
        return perBody[2];
      });
      body.close();
      m._free(shapes);
      m._free(poses);
      m._free(out);
      return { times: results, ready: window.sscapeApp.timings.sinceNavigationMs, model: window.sscapeApp.timings.modelMs };
    }, rows);
  } finally {
    await browser.close();
  }
}

const server = await serve(webDir);
const native = [], web = [], ready = [];
try {
  for (let r = 0; r < rounds; ++r) {
    native.push(nativeRound());
    const b = await browserRound(server);
    web.push(b.times);
    ready.push(b.ready);
    console.log(`round ${r + 1}: native ${native[r].map((t) => t.toFixed(1)).join(' / ')} us, browser ${b.times.map((t) => t.toFixed(1)).join(' / ')} us, ` +
      `page ready ${b.ready.toFixed(0)} ms after navigation (model fetched and verified at ${b.model.toFixed(0)} ms of the script)`);
  }
} finally {
  await server.close();
}
const median = (values) => [...values].sort((a, b) => a - b)[Math.floor(values.length / 2)];
console.log(`\n${'synthesis (median of rounds)'.padEnd(30)} ${'native us'.padStart(10)} ${'browser us'.padStart(11)} ${'ratio'.padStart(6)}  (target <= 2)`);
let worstRatio = 0;
rows.forEach(([name], i) => {
  const n = median(native.map((x) => x[i])), w = median(web.map((x) => x[i]));
  worstRatio = Math.max(worstRatio, w / n);
  console.log(`${name.padEnd(30)} ${n.toFixed(1).padStart(10)} ${w.toFixed(1).padStart(11)} ${(w / n).toFixed(2).padStart(6)}`);
});
const gz = (file) => zlib.gzipSync(fs.readFileSync(path.join(webDir, file)), { level: 9 }).length;
const code = ['sscape_runtime.wasm', 'sscape_runtime.mjs', 'sscape.mjs'];
const codeBytes = code.reduce((sum, f) => sum + gz(f), 0);
console.log(`page ready (model fetched, verified, first body drawn): median ${median(ready).toFixed(0)} ms after navigation (target <= 1000)`);
console.log(`WebAssembly + JavaScript gzipped: ${code.map((f) => `${f} ${gz(f)}`).join(', ')} = ${codeBytes} bytes (target <= 1,048,576); ` +
  `the model file as shipped ${fs.statSync(path.join(webDir, 'sscape-default.sscape')).size} bytes; three.js ${gz('three.module.min.js')} gzipped`);
console.log(`worst browser/native ratio ${worstRatio.toFixed(2)}`);
