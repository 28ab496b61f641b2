// Runs the Khronos glTF-Validator (npm package gltf-validator) on glTF/GLB files.
//   node validate_gltf.cjs NODE_MODULES_DIR FILE...
// Prints one line per file with the issue counts, then every error and warning; exits 0 when
// every file has no errors and no warnings, 1 otherwise, 2 on a usage or read failure.
'use strict';
const fs = require('fs');
const path = require('path');

const [modules, ...files] = process.argv.slice(2);
if (!modules || files.length === 0) {
  console.error('usage: node validate_gltf.cjs NODE_MODULES_DIR FILE...');
  process.exit(2);
}
const validator = require(path.resolve(modules, 'gltf-validator'));

async function check(file) {
  const bytes = new Uint8Array(fs.readFileSync(file));
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0,
    // External resources (the .bin of a .gltf) are read next to the file.
    externalResourceFunction: (uri) =>
      new Promise((resolve, reject) => {
        try {
          resolve(new Uint8Array(fs.readFileSync(path.join(path.dirname(file), decodeURIComponent(uri)))));
        } catch (e) {
          reject(e.toString());
        }
      }),
  });
  const i = report.issues;
  console.log(`${file}: errors ${i.numErrors} warnings ${i.numWarnings} infos ${i.numInfos} hints ${i.numHints}`);
  for (const m of i.messages)
    if (m.severity <= 1)
      console.log(`  ${m.severity === 0 ? 'error' : 'warning'} ${m.code} at ${m.pointer || ''}: ${m.message}`);
  return i.numErrors === 0 && i.numWarnings === 0;
}

(async () => {
  let ok = true;
  for (const f of files) {
    try {
      ok = (await check(f)) && ok;
    } catch (e) {
      console.error(`${f}: ${e}`);
      process.exit(2);
    }
  }
  process.exit(ok ? 0 : 1);
})();
