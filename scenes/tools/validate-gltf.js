#!/usr/bin/env node
// Runs the Khronos glTF validator (npm gltf-validator, installed by scripts/install-deps into
// build/tools/node_modules) over each .glb/.gltf given and prints a one-line summary per file plus
// every error and warning. Exit status: 0 all files have zero errors, 1 some file has errors,
// 2 usage / the validator cannot be found / a file cannot be read.
//
//   node scenes/tools/validate-gltf.js [--modules DIR] [--json] FILE...
//
// --modules DIR  where node_modules/gltf-validator lives (default: <repo>/build/tools)
// --json         print the validator's full JSON report per file instead of the summary
'use strict';
const fs = require('fs');
const path = require('path');

function usage(msg) {
  if (msg) console.error('validate-gltf: ' + msg);
  console.error('usage: validate-gltf.js [--modules DIR] [--json] FILE...');
  process.exit(2);
}

const args = process.argv.slice(2);
let modulesDir = path.resolve(__dirname, '..', '..', 'build', 'tools');
let json = false;
const files = [];
for (let i = 0; i < args.length; ++i) {
  if (args[i] === '--modules') {
    if (i + 1 >= args.length) usage('--modules needs a directory');
    modulesDir = path.resolve(args[++i]);
  } else if (args[i] === '--json') {
    json = true;
  } else if (args[i].startsWith('--')) {
    usage('unknown option ' + args[i]);
  } else {
    files.push(args[i]);
  }
}
if (files.length === 0) usage('no input files');

let validator;
try {
  validator = require(path.join(modulesDir, 'node_modules', 'gltf-validator'));
} catch (e) {
  console.error(`validate-gltf: cannot load gltf-validator from ${modulesDir}/node_modules ` +
                `(run scripts/install-deps): ${e.message}`);
  process.exit(2);
}

const severityName = ['error', 'warning', 'info', 'hint'];

async function validateOne(file) {
  let bytes;
  try {
    bytes = new Uint8Array(fs.readFileSync(file));
  } catch (e) {
    console.error(`validate-gltf: ${file}: cannot read: ${e.message}`);
    return 'unreadable';
  }
  const dir = path.dirname(path.resolve(file));
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0,  // 0 = no limit: a test must see every error, not the first ten
    // External buffers/images (only .gltf uses them) resolve next to the file.
    externalResourceFunction: (uri) => new Promise((resolve, reject) => {
      fs.readFile(path.resolve(dir, decodeURIComponent(uri)), (err, data) => {
        if (err) reject(err.toString()); else resolve(new Uint8Array(data));
      });
    }),
  });
  const i = report.issues;
  if (json) {
    console.log(JSON.stringify(report, null, 1));
  } else {
    console.log(`${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ` +
                `${i.numHints} hints (validator ${report.validatorVersion})`);
    for (const m of i.messages) {
      if (m.severity > 1) continue;
      console.log(`  ${severityName[m.severity]} ${m.code} at ${m.pointer || '-'}: ${m.message}`);
    }
  }
  return i.numErrors === 0 ? 'ok' : 'errors';
}

(async () => {
  let status = 0;
  for (const f of files) {
    let r;
    try {
      r = await validateOne(f);
    } catch (e) {
      console.error(`validate-gltf: ${f}: validator failed: ${e}`);
      r = 'errors';
    }
    if (r === 'unreadable') status = 2;
    else if (r === 'errors' && status === 0) status = 1;
  }
  process.exit(status);
})();
