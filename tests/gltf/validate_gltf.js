// Validates glTF files with the Khronos glTF validator (npm package gltf-validator).
// usage: node validate_gltf.js FILE...   exit 0 = no errors, 1 = errors, 77 = validator not installed
let validator;
try {
  validator = require('gltf-validator');
} catch (e) {
  console.log('SKIPPED: npm package gltf-validator is not installed (setup.sh installs it)');
  process.exit(77);
}
const fs = require('fs');

(async () => {
  let failed = false;
  for (const file of process.argv.slice(2)) {
    const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)));
    const i = report.issues;
    console.log(`${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos`);
    for (const m of i.messages.filter((m) => m.severity <= 1).slice(0, 20))
      console.log(`  ${m.severity === 0 ? 'error' : 'warning'} ${m.code}: ${m.message} ${m.pointer || ''}`);
    if (i.numErrors > 0) failed = true;
  }
  process.exit(failed ? 1 : 0);
})().catch((e) => {
  console.error(e);
  process.exit(1);
});
