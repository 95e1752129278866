#!/usr/bin/env node
// Validates a .glb/.gltf file with the Khronos glTF validator and prints its
// report as JSON. Exit status: 0 no errors, 1 errors, 2 validator missing,
// 3 file unreadable. The validator is an npm package that pfill does not
// install: `npm install -g gltf-validator`, or `npm install gltf-validator`
// in any folder named by PFILL_GLTF_VALIDATOR_DIR.
'use strict';
const fs = require('fs');
const path = require('path');
const { execSync } = require('child_process');

function loadValidator() {
  // scripts/install-deps.sh installs it into the repository's .tools/.
  const candidates = ['gltf-validator', path.join(__dirname, '..', '.tools', 'node_modules', 'gltf-validator')];
  if (process.env.PFILL_GLTF_VALIDATOR_DIR)
    candidates.push(path.join(process.env.PFILL_GLTF_VALIDATOR_DIR, 'node_modules', 'gltf-validator'));
  try {
    const globalRoot = execSync('npm root -g', { stdio: ['ignore', 'pipe', 'ignore'] }).toString().trim();
    candidates.push(path.join(globalRoot, 'gltf-validator'));
  } catch (e) { /* no npm: only the other candidates */ }
  for (const c of candidates) {
    try { return require(c); } catch (e) { /* try the next */ }
  }
  return null;
}

const file = process.argv[2];
if (!file) {
  console.error('usage: validate_gltf.js FILE.glb');
  process.exit(3);
}
const validator = loadValidator();
if (!validator) {
  console.error('gltf-validator not found (npm install -g gltf-validator)');
  process.exit(2);
}
let bytes;
try {
  bytes = new Uint8Array(fs.readFileSync(file));
} catch (e) {
  console.error(`cannot read ${file}: ${e.message}`);
  process.exit(3);
}
validator.validateBytes(bytes, { maxIssues: 100 })
  .then((report) => {
    console.log(JSON.stringify(report, null, 2));
    process.exit(report.issues.numErrors > 0 ? 1 : 0);
  })
  .catch((error) => {
    console.error(`validation failed: ${error}`);
    process.exit(1);
  });
