#!/usr/bin/env node
// Validates .glb/.gltf files with the Khronos glTF validator (npm gltf-validator, pinned in
// package.json; installed by scripts/install-validators.sh).
// Usage: node validate_gltf.js FILE...
// Prints one summary line per file: "FILE: errors=N warnings=N infos=N hints=N" and every
// error/warning message. Exit 0 when every file has 0 errors, 1 otherwise, 2 on a usage or
// loading problem (file unreadable, validator missing).
'use strict';
const fs = require('fs');
const path = require('path');

let validator;
try {
  validator = require('gltf-validator');
} catch (e) {
  console.error('validate_gltf.js: cannot load gltf-validator (' + e.message +
                '); run scripts/install-validators.sh');
  process.exit(2);
}

async function validateFile(file) {
  const bytes = new Uint8Array(fs.readFileSync(file));
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0,
    writeTimestamp: false,
    externalResourceFunction: (uri) => new Promise((resolve, reject) => {
      const p = path.resolve(path.dirname(file), decodeURIComponent(uri));
      fs.readFile(p, (err, data) => (err ? reject(err.toString()) : resolve(new Uint8Array(data))));
    }),
  });
  const s = report.issues;
  console.log(`${file}: errors=${s.numErrors} warnings=${s.numWarnings} infos=${s.numInfos} ` +
              `hints=${s.numHints} validator=${report.validatorVersion}`);
  for (const m of s.messages) {
    if (m.severity <= 1) {
      console.log(`  ${m.severity === 0 ? 'ERROR' : 'WARNING'} ${m.code} ${m.pointer || ''}: ${m.message}`);
    }
  }
  return s.numErrors;
}

async function main() {
  const files = process.argv.slice(2);
  if (files.length === 0) {
    console.error('usage: node validate_gltf.js FILE.glb|FILE.gltf ...');
    process.exit(2);
  }
  let errors = 0;
  for (const f of files) {
    try {
      errors += await validateFile(f);
    } catch (e) {
      console.error(`${f}: cannot validate: ${e}`);
      process.exit(2);
    }
  }
  process.exit(errors === 0 ? 0 : 1);
}
main();
