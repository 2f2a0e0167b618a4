// Validates a .glb with the Khronos glTF validator (npm gltf-validator); prints the report's
// numbers and every error, and exits 0 only with zero errors. Usage: node validate_gltf.js FILE
// (NODE_PATH must reach the installed gltf-validator; scripts/install-test-tools.sh).
const fs = require('fs');
const validator = require('gltf-validator');
const file = process.argv[2];
validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {maxIssues: 1000})
  .then((report) => {
    const i = report.issues;
    console.log(`errors ${i.numErrors} warnings ${i.numWarnings} infos ${i.numInfos}`);
    for (const m of i.messages) if (m.severity === 0) console.log(`${m.code}: ${m.message} ${m.pointer || ''}`);
    process.exit(i.numErrors === 0 ? 0 : 1);
  })
  .catch((e) => { console.error(`validator failed: ${e}`); process.exit(2); });
