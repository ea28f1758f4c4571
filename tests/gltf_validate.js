// Runs the Khronos glTF validator (npm gltf-validator, installed by scripts/setup.sh into
// tools/) on one .gltf: prints its issues as JSON, exits 1 when it reports an error.
// Usage: node gltf_validate.js VALIDATOR_MODULE_DIR FILE.gltf
const fs = require('fs');
const validator = require(process.argv[2]);
const bytes = new Uint8Array(fs.readFileSync(process.argv[3]));
validator.validateBytes(bytes).then(report => {
    console.log(JSON.stringify(report.issues));
    process.exit(report.issues.numErrors ? 1 : 0);
}).catch(e => {
    console.error(String(e));
    process.exit(2);
});
