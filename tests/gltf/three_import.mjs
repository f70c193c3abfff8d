// Imports a GLB with three.js's GLTFLoader (npm three), as a web viewer or engine would, and checks
// what sscape put in it: every level a skinned mesh on the one skeleton, every morph target, the
// _MODEL_VERTEX attribute. In Node the embedded PNG texture cannot be decoded (no image decoder):
// the loader says so and goes on; a browser loads it.
// usage: node three_import.mjs NPM_MODULES FILE LEVELS MORPHS BONES   exit 0 ok, 1 wrong, 77 three missing
import fs from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';

const [modules, file, levels, morphs, bones] = process.argv.slice(2);
const loaderPath = path.join(modules, 'three/examples/jsm/loaders/GLTFLoader.js');
if (!fs.existsSync(loaderPath)) {
  console.log('SKIPPED: npm package three is not installed (setup.sh test installs it)');
  process.exit(77);
}
const { GLTFLoader } = await import(pathToFileURL(loaderPath).href);
globalThis.self = globalThis;  // the loader's texture path looks for it
const bytes = fs.readFileSync(file);
new GLTFLoader().parse(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength), '', (gltf) => {
  const meshes = [];
  gltf.scene.traverse((o) => { if (o.isSkinnedMesh) meshes.push(o); });
  let ok = meshes.length === Number(levels);
  for (const m of meshes) {
    const targets = Object.keys(m.morphTargetDictionary || {}).length;
    console.log(`${m.name}: ${m.geometry.attributes.position.count} vertices, ${targets} morph targets, ` +
                `${m.skeleton.bones.length} bones, _MODEL_VERTEX ${'_model_vertex' in m.geometry.attributes}`);
    ok = ok && targets === Number(morphs) && m.skeleton.bones.length === Number(bones) && '_model_vertex' in m.geometry.attributes;
  }
  console.log(ok ? `three.js imported ${meshes.length} levels` : 'three.js import: not what was written');
  process.exit(ok ? 0 : 1);
}, (e) => {
  console.error('three.js could not load the file:', e.message || e);
  process.exit(1);
});
