// Runs the Khronos glTF validator (npm gltf-validator, installed by scripts/setup.sh into
// tools/) on one .gltf: prints its issues as JSON, exits 1 when it reports an error.
// External resources (buffers, images by relative URI) are loaded relative to the file's
// folder, so they are validated too; a missing one is the validator's IO_ERROR.
// Usage: node gltf_validate.js VALIDATOR_MODULE_DIR FILE.gltf
const fs = require('fs');
const path = require('path');
const validator = require(process.argv[2]);
const file = process.argv[3];
const bytes = new Uint8Array(fs.readFileSync(file));
validator.validateBytes(bytes, {
    uri: path.basename(file),
    externalResourceFunction: uri => new Promise((resolve, reject) => {
        fs.readFile(path.resolve(path.dirname(file), decodeURIComponent(uri)), (e, data) => {
            if (e)
                reject(String(e));
            else
                resolve(new Uint8Array(data));
        });
    }),
}).then(report => {
    console.log(JSON.stringify(report.issues));
    process.exit(report.issues.numErrors ? 1 : 0);
}).catch(e => {
    console.error(String(e));
    process.exit(2);
});
